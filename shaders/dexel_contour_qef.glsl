// shaders/dexel_contour_qef.glsl - part of dexel_contour.comp: sharp-feature vertex placement, i.e.
// crossing normals estimated from neighbouring rays (contour::crossing_normal) and the QEF vertex
// (contour::qef_vertex), compute/contour/contour_qef.cpp mirrored operation for operation: the same association,
// comparisons (incl. the !(x > y) forms), tie rules and constants, in double precision with `precise`
// (no contraction into multiply-adds), so the results are the CPU's doubles bit for bit on lavapipe
// (Vulkan leaves double sqrt/division rounding and denormals to the device; see gpu_contourer.hpp).
// Needs dexel_contour_rays.glsl (ray_meta, ray_interval, finite) and pc.cells.

const double kNormalWindow = 2.0lf;     // contour::kNormalWindow, grid units
const double kCentralSlopeTol = 0.5lf;  // contour::kCentralSlopeTol
const double kOneSidedSlopeMax = 1.0lf; // contour::kOneSidedSlopeMax
const double kCreaseResidual = 0.25lf; // contour::kCreaseResidual
const double kOpposedNormalCos = -0.8lf; // contour::kOpposedNormalCos
const double kCornerFillReach = 0.5lf;  // contour::kCornerFillReach
const double kCornerFillDepth = 0.3lf;  // contour::kCornerFillDepth
const double kCornerFillCos = -0.5lf;   // contour::kCornerFillCos
const double kCornerFillFront = 0.1lf;  // contour::kCornerFillFront
const double kBorrowReach = 0.25lf;     // contour::kBorrowReach
const double kBorrowSheetCos = 0.0lf;   // contour::kBorrowSheetCos
const double kBorrowWrongCos = 0.7lf;   // contour::kBorrowWrongCos
const double kFitPlaneRatio = 4.0lf;    // contour::kFitPlaneRatio
const double kFitPlaneSpread = 1e-6lf;  // contour::kFitPlaneSpread
const double kQefTruncation = 0.05lf;   // contour::kQefTruncation
const int kJacobiSweeps = 5;            // contour::kJacobiSweeps
const double kJacobiTolerance = 1e-9lf; // contour::kJacobiTolerance

// The end of kind `exit_end` on ray r of set a nearest to t within kNormalWindow (ties: the lower one).
bool nearest_end(int a, uint r, bool exit_end, double t, inout double depth) {
    uint m = ray_meta(a, r), cnt = m & 127u;
    bool found = false;
    double best = 0.0lf;
    for (uint i = 0u; i < cnt; ++i) {
        float en, ex;
        uint pair;
        ray_interval(a, r, m, i, en, ex, pair);
        float ef = exit_end ? ex : en;
        if (!finite(ef)) continue;
        double e = double(ef);
        precise double d = abs(e - t);
        if (d <= kNormalWindow && (!found || d < best)) {
            best = d;
            depth = e;
            found = true;
        }
    }
    return found;
}

// True when depth t lies inside an interval of ray r of set a (enter <= t < exit; contour inside_at()).
bool inside_at(int a, uint r, double t) {
    uint m = ray_meta(a, r), cnt = m & 127u;
    for (uint i = 0u; i < cnt; ++i) {
        float en, ex;
        uint pair;
        ray_interval(a, r, m, i, en, ex, pair);
        if (double(en) <= t && t < double(ex)) return true;
    }
    return false;
}

// contour_qef.cpp gap_between: the ray of set `dir` through node n with its a coordinate at node depth s has an
// interval end strictly between n[dir] and w2 (false when s lies outside the lattice).
bool gap_between(int a, ivec3 n, int dir, int w2, double s) {
    bool cut = false;
    if (s >= 0.0lf && s <= double(pc.cells[a])) {
        ivec3 p = n;
        p[a] = int(s);
        int du = (dir + 1) % 3, dv = (dir + 2) % 3;
        uint r = uint(p[du]) + uint(pc.cells[du] + 1) * uint(p[dv]);
        double lo_w = double(min(n[dir], w2)), hi_w = double(max(n[dir], w2));
        uint m = ray_meta(dir, r), cnt = m & 127u;
        for (uint i = 0u; i < cnt && !cut; ++i) {
            float en, ex;
            uint pair;
            ray_interval(dir, r, m, i, en, ex, pair);
            double den = double(en), dex = double(ex);
            bool in_en = finite(en) && lo_w < den && den < hi_w;
            bool in_ex = finite(ex) && lo_w < dex && dex < hi_w;
            cut = cut || in_en || in_ex;
        }
    }
    return cut;
}

// contour_qef.cpp same_surface: a one-sided slope to the end at depth e on the ray at w2 reads the crossing's surface
// unless the lattice line along `dir` at the node on the material side of both ends is cut between the rays.
bool same_surface(int a, ivec3 n, int dir, int w2, bool exit_end, double t, double e) {
    double s = exit_end ? ceil(min(t, e)) - 1.0lf : ceil(max(t, e));
    return !gap_between(a, n, dir, w2, s);
}

// Slope of the height field of set a along lattice direction `dir` at node n (contour slope()): the
// neighbour rays u -+ 1 or v -+ 1, bounds-checked against the set's nu / nv (= cells + 1). `is_flat`: a neighbour
// end at exactly depth t; `extremum`: one side alone, the other side's surface beyond the window the other way
// (a trough or ridge one ray wide; the other ray's occupancy at depth t tells which way); `lone`: one side alone
// gives a slope other than 0.
bool slope(int a, ivec3 n, int dir, bool exit_end, double t, out double g, inout bool crease, out bool is_flat, out bool extremum,
           out bool lone) {
    int ua = (a + 1) % 3, va = (a + 2) % 3;
    int w = n[dir];
    bool u_dir = dir == ua;
    int limit = (u_dir ? pc.cells[ua] : pc.cells[va]) + 1;
    uint stride = uint(pc.cells[ua] + 1);
    int u = n[ua], v = n[va];
    double em = 0.0lf, ep = 0.0lf;
    bool has_m = false, has_p = false;
    if (w - 1 >= 0)
        has_m = nearest_end(a, u_dir ? uint(u - 1) + stride * uint(v) : uint(u) + stride * uint(v - 1), exit_end, t, em);
    if (w + 1 < limit)
        has_p = nearest_end(a, u_dir ? uint(u + 1) + stride * uint(v) : uint(u) + stride * uint(v + 1), exit_end, t, ep);
    precise double dm = t - em;
    precise double dp = ep - t;
    g = 0.0lf;
    is_flat = (has_m && dm == 0.0lf) || (has_p && dp == 0.0lf);
    extremum = false;
    lone = false;
    if (has_m != has_p) {
        bool other_exists = has_m ? w + 1 < limit : w - 1 >= 0;
        if (other_exists) {
            uint ro = has_m ? (u_dir ? uint(u + 1) + stride * uint(v) : uint(u) + stride * uint(v + 1))
                            : (u_dir ? uint(u - 1) + stride * uint(v) : uint(u) + stride * uint(v - 1));
            bool higher = inside_at(a, ro, t) == exit_end;
            bool other_rises = has_m ? higher : !higher;
            double d = has_m ? dm : dp;
            extremum = d != 0.0lf && (d > 0.0lf) != other_rises;
        }
    }
    if (has_m && has_p) {
        precise double spread = dp - dm;
        if (abs(spread) <= kCentralSlopeTol) {
            precise double mid = (dm + dp) * 0.5lf;
            g = mid;
            return true;
        }
        // A crease between the rays: a side at exactly depth t is a flat face the crossing lies on.
        if ((dm == 0.0lf) != (dp == 0.0lf)) {
            crease = true;
            return true;
        }
        return false;
    }
    // One side alone (a sharp edge): only a gentle slope (contour::kOneSidedSlopeMax), with no gap between the rays.
    if (has_m) {
        g = dm;
        lone = dm != 0.0lf;
        return abs(dm) <= kOneSidedSlopeMax && same_surface(a, n, dir, w - 1, exit_end, t, em);
    }
    if (has_p) {
        g = dp;
        lone = dp != 0.0lf;
        return abs(dp) <= kOneSidedSlopeMax && same_surface(a, n, dir, w + 1, exit_end, t, ep);
    }
    return false;
}

// contour::crossing_normal: outward unit normal at the crossing at depth t on the edge from n along a
// (start_inside: the crossing is an interval exit). False (normal = 0) without a neighbour end; `crease`:
// a crease's flat side gave the normal; `one_sided`: a slope other than 0 came from one side alone.
bool crossing_normal(int a, ivec3 n, bool start_inside, double t, out dvec3 normal, out bool crease, out bool one_sided) {
    int b = (a + 1) % 3, c = (a + 2) % 3;
    double gb, gc;
    normal = dvec3(0.0lf);
    crease = false;
    bool flat_b, flat_c, ext_b, ext_c, lone_b, lone_c;
    bool ok_b = slope(a, n, b, start_inside, t, gb, crease, flat_b, ext_b, lone_b);
    bool ok_c = slope(a, n, c, start_inside, t, gc, crease, flat_c, ext_c, lone_c);
    // A trough or ridge one ray wide on a face flat along the other direction: slope 0 (contour crossing_normal).
    if (ext_b && flat_c) {
        gb = 0.0lf;
        ok_b = true;
        lone_b = false;
    }
    if (ext_c && flat_b) {
        gc = 0.0lf;
        ok_c = true;
        lone_c = false;
    }
    one_sided = lone_b || lone_c;
    if (!ok_b || !ok_c) {
        crease = false;
        one_sided = false;
        return false;
    }
    precise double len2 = (1.0lf + gb * gb) + gc * gc;
    precise double len = sqrt(len2);
    double sa = start_inside ? 1.0lf : -1.0lf;
    double sb = start_inside ? -gb : gb;
    double sc = start_inside ? -gc : gc;
    precise double na = sa / len;
    precise double nb = sb / len;
    precise double nc = sc / len;
    normal[a] = na;
    normal[b] = nb;
    normal[c] = nc;
    return true;
}

// The QEF sums of qef_vertex for one more crossing p with normal nn, relative to `mass`: m (row-major
// 3x3, j * 3 + k) += nn nn^T, r += nn (nn . (p - mass)). Called in ascending edge order, as the CPU sums.
void qef_add(inout double m[9], inout double r[3], dvec3 nn, dvec3 p, dvec3 mass) {
    precise double dx = p.x - mass.x;
    precise double dy = p.y - mass.y;
    precise double dz = p.z - mass.z;
    precise double s = (nn.x * dx + nn.y * dy) + nn.z * dz;
    [[unroll]] for (int j = 0; j < 3; ++j) {
        [[unroll]] for (int k = 0; k < 3; ++k) {
            precise double mjk = m[3 * j + k] + nn[j] * nn[k];
            m[3 * j + k] = mjk;
        }
        precise double rj = r[j] + nn[j] * s;
        r[j] = rj;
    }
}

// One Jacobi rotation zeroing m[p][q] of the symmetric m, accumulated into the columns of v (row-major).
void qef_rotate(inout double m[9], inout double v[9], int p, int q) {
    double apq = m[3 * p + q];
    if (apq == 0.0lf) return;
    precise double theta = (m[3 * q + q] - m[3 * p + p]) / (2.0lf * apq);
    precise double root = sqrt(theta * theta + 1.0lf);
    precise double t = 1.0lf / (abs(theta) + root);
    if (theta < 0.0lf) t = -t;
    precise double croot = sqrt(t * t + 1.0lf);
    precise double c = 1.0lf / croot;
    precise double s = t * c;
    int r = 3 - p - q;  // the third index
    double arp = m[3 * r + p], arq = m[3 * r + q];
    precise double mrp = c * arp - s * arq;
    precise double mrq = s * arp + c * arq;
    precise double mpp = m[3 * p + p] - t * apq;
    precise double mqq = m[3 * q + q] + t * apq;
    m[3 * r + p] = mrp;
    m[3 * p + r] = mrp;
    m[3 * r + q] = mrq;
    m[3 * q + r] = mrq;
    m[3 * p + p] = mpp;
    m[3 * q + q] = mqq;
    m[3 * p + q] = 0.0lf;
    m[3 * q + p] = 0.0lf;
    [[unroll]] for (int k = 0; k < 3; ++k) {
        double vkp = v[3 * k + p], vkq = v[3 * k + q];
        precise double nkp = c * vkp - s * vkq;
        precise double nkq = s * vkp + c * vkq;
        v[3 * k + p] = nkp;
        v[3 * k + q] = nkq;
    }
}

// contour_qef.cpp jacobi_eigen: diagonalises the symmetric m (row-major) in place by cyclic Jacobi sweeps until the
// off-diagonal sum is at most kJacobiTolerance times the diagonal sum (the CPU's test, in its order; true before any
// sweep for axis-aligned faces); v gets the eigenvectors as columns.
void qef_jacobi(inout double m[9], out double v[9]) {
    v = double[9](1.0lf, 0.0lf, 0.0lf, 0.0lf, 1.0lf, 0.0lf, 0.0lf, 0.0lf, 1.0lf);
    [[dont_unroll]] for (int sweep = 0; sweep < kJacobiSweeps; ++sweep) {
        precise double off = (abs(m[1]) + abs(m[2])) + abs(m[5]);
        precise double diag = (abs(m[0]) + abs(m[4])) + abs(m[8]);
        precise double lim = kJacobiTolerance * diag;
        if (off <= lim) break;
        qef_rotate(m, v, 0, 1);
        qef_rotate(m, v, 0, 2);
        qef_rotate(m, v, 1, 2);
    }
}

// contour::fit_normal: the outward unit normal of the plane fitted to `count` points (the eigenvector of the
// smallest eigenvalue of their scatter matrix about `mass`), each with its edge axis and exit flag; false
// when fewer than 3, not spanning a plane, or balanced. Points in ascending edge order, as the CPU's.
bool fit_normal(dvec3 mass, dvec3 pts[12], int axes[12], bool exits[12], int count, out dvec3 normal) {
    normal = dvec3(0.0lf);
    if (count < 3) return false;
    double m[9] = double[9](0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf);
    for (int i = 0; i < count; ++i) {
        precise double dx = pts[i].x - mass.x;
        precise double dy = pts[i].y - mass.y;
        precise double dz = pts[i].z - mass.z;
        double d[3] = double[3](dx, dy, dz);
        [[unroll]] for (int j = 0; j < 3; ++j)
            [[unroll]] for (int k = 0; k < 3; ++k) {
                precise double mjk = m[3 * j + k] + d[j] * d[k];
                m[3 * j + k] = mjk;
            }
    }
    double v[9];
    qef_jacobi(m, v);
    int lo = 0;
    if (m[4] < m[4 * lo]) lo = 1;
    if (m[8] < m[4 * lo]) lo = 2;
    int mid = lo == 0 ? 1 : 0;
    [[unroll]] for (int k = 0; k < 3; ++k)
        if (k != lo && m[4 * k] < m[4 * mid]) mid = k;
    precise double need = kFitPlaneRatio * m[4 * lo];
    if (!(m[4 * mid] > need) || !(m[4 * mid] > kFitPlaneSpread)) return false;
    dvec3 n = dvec3(v[lo], v[3 + lo], v[6 + lo]);
    double side = 0.0lf;
    for (int i = 0; i < count; ++i) {
        double c = exits[i] ? n[axes[i]] : -n[axes[i]];
        precise double sc = side + c;
        side = sc;
    }
    if (!(side != 0.0lf)) return false;
    normal = side > 0.0lf ? n : -n;
    return true;
}

// contour_qef.cpp truncated_solve: the minimum-norm least-squares step y of the QEF sums a (row-major,
// by value: the Jacobi sweeps work on a copy) and r over the eigen-directions whose eigenvalue exceeds
// floor_ (floor_ < 0: kQefTruncation times the largest). Returns the largest eigenvalue.
double qef_truncated(double m[9], double r[3], double floor_, out double y[3]) {
    double v[9];
    qef_jacobi(m, v);
    double top = m[0];
    if (m[4] > top) top = m[4];
    if (m[8] > top) top = m[8];
    precise double rel = kQefTruncation * top;
    double fl = floor_ < 0.0lf ? rel : floor_;
    y = double[3](0.0lf, 0.0lf, 0.0lf);
    [[unroll]] for (int k = 0; k < 3; ++k) {
        double lambda = m[4 * k];
        if (!(lambda > fl)) continue;
        precise double w = ((v[k] * r[0] + v[3 + k] * r[1]) + v[6 + k] * r[2]) / lambda;
        [[unroll]] for (int j = 0; j < 3; ++j) {
            precise double yj = y[j] + w * v[3 * j + k];
            y[j] = yj;
        }
    }
    return top;
}

// contour::qef_vertex from the sums of qef_add (count > 0 crossings with a normal): the truncated
// eigen-solve relative to `mass`; when outside the cell [lo, lo + 1], coordinates outside are fixed on the
// nearer face and the rest re-solved (at most three times), then clamped; the clamped mass point when the
// minimiser is not finite or the matrix is zero.
dvec3 qef_solve(dvec3 mass, double m[9], double r[3], dvec3 lo) {
    precise dvec3 hi = lo + dvec3(1.0lf);
    dvec3 fallback = min(max(mass, lo), hi);
    double y[3];
    double top = qef_truncated(m, r, -1.0lf, y);
    if (!(top > 0.0lf)) return fallback;
    precise double floor_ = kQefTruncation * top;
    double base[3] = double[3](mass.x, mass.y, mass.z);
    bool held[3] = bool[3](false, false, false);
    [[dont_unroll]] for (int round = 0; round < 3; ++round) {
        bool moved = false;
        [[unroll]] for (int j = 0; j < 3; ++j) {
            if (held[j]) continue;
            precise double x = base[j] + y[j];
            if (isnan(x) || isinf(x)) return fallback;  // NaN normals or points
            if (x < lo[j] || x > hi[j]) {
                held[j] = true;
                base[j] = x < lo[j] ? lo[j] : hi[j];
                moved = true;
            }
        }
        if (!moved) break;
        // The sums over the free coordinates relative to the new base: fixed rows and columns zeroed,
        // r' = r - A (base - mass).
        precise double d0 = base[0] - mass.x;
        precise double d1 = base[1] - mass.y;
        precise double d2 = base[2] - mass.z;
        double af[9], rf[3];
        [[unroll]] for (int j = 0; j < 3; ++j) {
            precise double rj = r[j] - ((m[3 * j] * d0 + m[3 * j + 1] * d1) + m[3 * j + 2] * d2);
            rf[j] = held[j] ? 0.0lf : rj;
            [[unroll]] for (int k = 0; k < 3; ++k) af[3 * j + k] = held[j] || held[k] ? 0.0lf : m[3 * j + k];
        }
        qef_truncated(af, rf, floor_, y);
    }
    precise dvec3 x = dvec3(base[0] + y[0], base[1] + y[1], base[2] + y[2]);
    return min(max(x, lo), hi);
}
