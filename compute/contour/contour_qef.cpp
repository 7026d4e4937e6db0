// compute/contour/contour_qef.cpp - crossing normals from neighbouring rays and the QEF vertex (see the header).
// Every expression is written in the order shaders/dexel_contour_qef.glsl evaluates it; build with
// -ffp-contract=off so no multiply-add is fused.
#include "compute/contour/contour_qef.hpp"

#include <algorithm>
#include <cmath>

namespace tridex::compute::contour {
namespace {

/// The end of kind `exit_end` on `ray` nearest to t within kNormalWindow (ties: the lower one).
bool nearest_end(const std::vector<Interval>& ray, bool exit_end, double t, double& depth) {
    bool found = false;
    double best = 0.0;
    for (const Interval& iv : ray) {
        const double e = exit_end ? static_cast<double>(iv.exit) : static_cast<double>(iv.enter);
        if (!std::isfinite(e)) continue;
        const double d = std::abs(e - t);
        if (d <= kNormalWindow && (!found || d < best)) {
            best = d;
            depth = e;
            found = true;
        }
    }
    return found;
}

/// True when the ray of set `dir` through the crossing's ray at node depth `s` along a (the lattice line joining the
/// crossing's ray, at coordinate n[dir], to its neighbour at `w2`) has an interval end strictly between the two rays:
/// the material between them is cut at that depth. False when depth s lies outside the lattice.
bool gap_between(const TriDexel& model, int a, const Node& n, int dir, int w2, double s) {
    if (!(s >= 0.0) || s > static_cast<double>(model.lattice.cells[a])) return false;
    Node p = n;
    p[a] = static_cast<int>(s);
    const RaySet& line = model.sets[dir];
    const double lo = std::min(n[dir], w2), hi = std::max(n[dir], w2);
    for (const Interval& iv : line.ray(p[(dir + 1) % 3], p[(dir + 2) % 3])) {
        const double en = static_cast<double>(iv.enter), ex = static_cast<double>(iv.exit);
        if (std::isfinite(en) && lo < en && en < hi) return true;
        if (std::isfinite(ex) && lo < ex && ex < hi) return true;
    }
    return false;
}

/// Whether a one-sided slope from the neighbour end at depth `e` (on the ray at w2 along `dir`) reads the same
/// surface as the crossing at depth t: false when the lattice line along `dir` at the node depth on the material
/// side of both ends (the node below the lower exit, or at or above the higher enter: half-open occupancy) is cut
/// between the two rays (the neighbour's end then lies on another face across a gap narrower than a cell: the far
/// wall of an air valley, the far face of a spike).
bool same_surface(const TriDexel& model, int a, const Node& n, int dir, int w2, bool exit_end, double t, double e) {
    const double s = exit_end ? std::ceil(std::min(t, e)) - 1.0 : std::ceil(std::max(t, e));
    return !gap_between(model, a, n, dir, w2, s);
}

/// Slope of the height field along one lattice direction at ray coordinate w (see crossing_normal).
/// `flat` is set when a neighbour end lies at exactly depth t (the crossing lies on a face flat along `dir`);
/// `extremum` when only one side has an end within the window and the other side's surface lies beyond the
/// window on the same side of t as that end (the crossing is the bottom of a trough or the top of a ridge one ray
/// wide along `dir`; the other side's occupancy at depth t tells on which side its surface lies); `lone` (set only,
/// never cleared) when one side alone gives a slope other than 0 (not the edge of a face flat across the ray axis).
bool slope(const TriDexel& model, int a, const Node& n, int dir, bool exit_end, double t, double& g, bool& crease,
           bool& flat, bool& extremum, bool& lone) {
    const RaySet& set = model.sets[a];
    const int w = n[dir];
    const bool u_dir = dir == (a + 1) % 3;
    const int limit = u_dir ? set.nu : set.nv;
    const int u = n[(a + 1) % 3], v = n[(a + 2) % 3];
    double em = 0.0, ep = 0.0;
    const bool has_m = w - 1 >= 0 && nearest_end(u_dir ? set.ray(u - 1, v) : set.ray(u, v - 1), exit_end, t, em);
    const bool has_p = w + 1 < limit && nearest_end(u_dir ? set.ray(u + 1, v) : set.ray(u, v + 1), exit_end, t, ep);
    const double dm = t - em, dp = ep - t;
    flat = (has_m && dm == 0.0) || (has_p && dp == 0.0);
    if (has_m != has_p) {
        // The missing side's surface: beyond t + window (its height above t) when that ray is inside at depth t
        // for an exit (material below the surface), outside for an enter; else below t - window.
        const bool other_exists = has_m ? w + 1 < limit : w - 1 >= 0;
        if (other_exists) {
            const bool in = inside_at(has_m ? (u_dir ? set.ray(u + 1, v) : set.ray(u, v + 1)) : (u_dir ? set.ray(u - 1, v) : set.ray(u, v - 1)), t);
            const bool higher = in == exit_end;
            // Along +dir: the missing side rises (higher on p, lower on m) or falls; the present side likewise.
            const bool other_rises = has_m ? higher : !higher;
            const double d = has_m ? dm : dp;
            extremum = d != 0.0 && (d > 0.0) != other_rises;
        }
    }
    if (has_m && has_p) {
        if (std::abs(dp - dm) <= kCentralSlopeTol) {
            g = (dm + dp) * 0.5;
            return true;
        }
        // A crease between the rays: a side at exactly the crossing's depth is a flat face across the
        // lattice axis (a box face, a flat floor) that the crossing lies on; else no normal.
        if ((dm == 0.0) != (dp == 0.0)) {
            g = 0.0;
            crease = true;
            return true;
        }
        return false;
    }
    // One side alone (a sharp edge): only a gentle slope, as a steep one may be another sheet's end, and only
    // when no gap lies between the two rays on the material side (same_surface).
    if (has_m) {
        g = dm;
        lone = dm != 0.0;
        return std::abs(dm) <= kOneSidedSlopeMax && same_surface(model, a, n, dir, w - 1, exit_end, t, em);
    }
    if (has_p) {
        g = dp;
        lone = dp != 0.0;
        return std::abs(dp) <= kOneSidedSlopeMax && same_surface(model, a, n, dir, w + 1, exit_end, t, ep);
    }
    return false;
}

/// One Jacobi rotation zeroing m[p][q] of the symmetric 3x3 `m`, accumulated into the columns of `v`.
void rotate(double m[3][3], double v[3][3], int p, int q) {
    const double apq = m[p][q];
    if (apq == 0.0) return;
    const double theta = (m[q][q] - m[p][p]) / (2.0 * apq);
    double t = 1.0 / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
    if (theta < 0.0) t = -t;
    const double c = 1.0 / std::sqrt(t * t + 1.0);
    const double s = t * c;
    const int r = 3 - p - q;  // the third index
    const double arp = m[r][p], arq = m[r][q];
    m[r][p] = c * arp - s * arq;
    m[p][r] = m[r][p];
    m[r][q] = s * arp + c * arq;
    m[q][r] = m[r][q];
    m[p][p] = m[p][p] - t * apq;
    m[q][q] = m[q][q] + t * apq;
    m[p][q] = 0.0;
    m[q][p] = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double vkp = v[k][p], vkq = v[k][q];
        v[k][p] = c * vkp - s * vkq;
        v[k][q] = s * vkp + c * vkq;
    }
}

}  // namespace

bool crossing_normal(const TriDexel& model, int a, const Node& n, bool start_inside, double t, Vec3& normal,
                     bool* at_crease, bool* one_sided) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    double gb = 0.0, gc = 0.0;
    bool crease = false, flat_b = false, flat_c = false, ext_b = false, ext_c = false, lone_b = false, lone_c = false;
    bool ok_b = slope(model, a, n, b, start_inside, t, gb, crease, flat_b, ext_b, lone_b);
    bool ok_c = slope(model, a, n, c, start_inside, t, gc, crease, flat_c, ext_c, lone_c);
    // A trough or ridge one ray wide along one direction (one-sided slope, the other side beyond the window
    // the other way) on a face flat along the other direction (a neighbour end at exactly depth t): a ledge of a
    // face flat across the ray axis (a flat-end floor between a deeper cut and a shallower floor), whose one
    // side is another face beyond its edge, so the slope there is 0.
    if (ext_b && flat_c) {
        gb = 0.0;
        ok_b = true;
        lone_b = false;
    }
    if (ext_c && flat_b) {
        gc = 0.0;
        ok_c = true;
        lone_c = false;
    }
    if (!ok_b || !ok_c) return false;
    if (at_crease) *at_crease = crease;
    if (one_sided) *one_sided = lone_b || lone_c;
    const double len = std::sqrt((1.0 + gb * gb) + gc * gc);
    // Exit (material below along a): grad(a - d(u, v)) = (1, -g_u, -g_v); an enter is the opposite.
    Vec3 out(0.0);
    out[a] = (start_inside ? 1.0 : -1.0) / len;
    out[b] = (start_inside ? -gb : gb) / len;
    out[c] = (start_inside ? -gc : gc) / len;
    normal = out;
    return true;
}

namespace {

/// Diagonalises the symmetric 3x3 `m` in place by cyclic Jacobi sweeps (at most kJacobiSweeps; stops once the
/// off-diagonal sum is at most kJacobiTolerance times the diagonal sum, at once for axis-aligned normals); `v` gets
/// the eigenvectors as columns, in the order of m's diagonal.
void jacobi_eigen(double m[3][3], double v[3][3]) {
    for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) v[j][k] = j == k ? 1.0 : 0.0;
    for (int sweep = 0; sweep < kJacobiSweeps; ++sweep) {
        const double off = (std::abs(m[0][1]) + std::abs(m[0][2])) + std::abs(m[1][2]);
        const double diag = (std::abs(m[0][0]) + std::abs(m[1][1])) + std::abs(m[2][2]);
        if (off <= kJacobiTolerance * diag) break;
        rotate(m, v, 0, 1);
        rotate(m, v, 0, 2);
        rotate(m, v, 1, 2);
    }
}

/// The truncated least-squares step of the QEF (see qef_vertex): for `a` = sum n n^T and `r` = sum n (n . (p -
/// base)), the minimum-norm y minimising |A y - r| over the eigen-directions of A whose eigenvalue exceeds
/// `floor`; floor < 0 means kQefTruncation times the largest eigenvalue. Returns that largest eigenvalue;
/// `dropped` is set when an eigenvalue was at most the floor. Coordinates whose row and column of `a` and
/// entry of `r` are zero get y = 0 exactly (no rotation mixes them in).
double truncated_solve(const double a[3][3], const double r[3], double floor, double y[3], bool& dropped) {
    double m[3][3] = {{a[0][0], a[0][1], a[0][2]}, {a[1][0], a[1][1], a[1][2]}, {a[2][0], a[2][1], a[2][2]}};
    double v[3][3];
    jacobi_eigen(m, v);
    double top = m[0][0];
    if (m[1][1] > top) top = m[1][1];
    if (m[2][2] > top) top = m[2][2];
    if (floor < 0.0) floor = kQefTruncation * top;
    y[0] = 0.0;
    y[1] = 0.0;
    y[2] = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double lambda = m[k][k];
        if (!(lambda > floor)) {
            dropped = true;
            continue;
        }
        const double w = ((v[0][k] * r[0] + v[1][k] * r[1]) + v[2][k] * r[2]) / lambda;
        for (int j = 0; j < 3; ++j) y[j] = y[j] + w * v[j][k];
    }
    return top;
}

}  // namespace

bool fit_normal(const Vec3& mass, const Vec3* points, const int* axes, const bool* exits, int count, Vec3& normal) {
    if (count < 3) return false;
    // Scatter matrix of the points about their mean, in the QEF's summation order.
    double m[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
    for (int i = 0; i < count; ++i) {
        const double d[3] = {points[i].x - mass.x, points[i].y - mass.y, points[i].z - mass.z};
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) m[j][k] = m[j][k] + d[j] * d[k];
    }
    double v[3][3];
    jacobi_eigen(m, v);
    // Smallest eigenvalue (first on ties) and the next one up.
    int lo = 0;
    if (m[1][1] < m[lo][lo]) lo = 1;
    if (m[2][2] < m[lo][lo]) lo = 2;
    int mid = lo == 0 ? 1 : 0;
    for (int k = 0; k < 3; ++k)
        if (k != lo && m[k][k] < m[mid][mid]) mid = k;
    if (!(m[mid][mid] > kFitPlaneRatio * m[lo][lo]) || !(m[mid][mid] > kFitPlaneSpread)) return false;
    const Vec3 n(v[0][lo], v[1][lo], v[2][lo]);
    // Outward: along each crossing's axis towards its outside node (+ for an exit).
    double side = 0.0;
    for (int i = 0; i < count; ++i) side = side + (exits[i] ? n[axes[i]] : -n[axes[i]]);
    if (!(side != 0.0)) return false;
    normal = side > 0.0 ? n : -n;
    return true;
}

Vec3 qef_vertex(const Vec3& mass, const Vec3* points, const Vec3* normals, int count, const Vec3& cell_lo, QefOutcome* outcome) {
    QefOutcome local;
    QefOutcome& out = outcome ? *outcome : local;
    out = QefOutcome{};
    const Vec3 hi = cell_lo + Vec3(1.0);
    const Vec3 fallback = glm::clamp(mass, cell_lo, hi);
    if (count <= 0) return fallback;
    out.normals = count;
    // A = sum n n^T, r = sum n (n . (p - mass)).
    double a[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
    double r[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < count; ++i) {
        const Vec3& nn = normals[i];
        const double dx = points[i].x - mass.x, dy = points[i].y - mass.y, dz = points[i].z - mass.z;
        const double s = (nn.x * dx + nn.y * dy) + nn.z * dz;
        for (int j = 0; j < 3; ++j) {
            for (int k = 0; k < 3; ++k) a[j][k] = a[j][k] + nn[j] * nn[k];
            r[j] = r[j] + nn[j] * s;
        }
    }
    double y[3];
    const double top = truncated_solve(a, r, -1.0, y, out.truncated);
    if (!(top > 0.0)) {  // not reached for unit normals; NaN normals end here
        out.truncated = false;
        out.rejected = true;
        return fallback;
    }
    // Cell-constrained minimisation (active set, constraints only added): coordinates of the minimiser
    // outside the cell are fixed on the nearer cell face and the QEF is minimised again over the free ones,
    // until the minimiser lies in the cell (at most three re-solves).
    double base[3] = {mass.x, mass.y, mass.z};
    bool fixed[3] = {false, false, false};
    for (int round = 0; round < 3; ++round) {
        bool moved = false;
        for (int j = 0; j < 3; ++j) {
            if (fixed[j]) continue;
            const double x = base[j] + y[j];
            if (!std::isfinite(x)) {  // NaN normals or points
                out.rejected = true;
                return fallback;
            }
            if (x < cell_lo[j] || x > hi[j]) {
                fixed[j] = true;
                base[j] = x < cell_lo[j] ? cell_lo[j] : hi[j];
                moved = true;
            }
        }
        if (!moved) break;
        out.clamped = true;
        // The QEF over the free coordinates, relative to the new base: rows and columns of fixed ones zeroed,
        // r' = r - A (base - mass).
        const double d[3] = {base[0] - mass.x, base[1] - mass.y, base[2] - mass.z};
        double af[3][3], rf[3];
        for (int j = 0; j < 3; ++j) {
            rf[j] = fixed[j] ? 0.0 : r[j] - ((a[j][0] * d[0] + a[j][1] * d[1]) + a[j][2] * d[2]);
            for (int k = 0; k < 3; ++k) af[j][k] = fixed[j] || fixed[k] ? 0.0 : a[j][k];
        }
        bool ignored = false;
        truncated_solve(af, rf, kQefTruncation * top, y, ignored);
    }
    Vec3 x(base[0] + y[0], base[1] + y[1], base[2] + y[2]);
    return glm::clamp(x, cell_lo, hi);
}

}  // namespace tridex::compute::contour
