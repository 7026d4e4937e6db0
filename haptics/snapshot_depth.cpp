// haptics/snapshot_depth.cpp - depth readings of points in an ActiveSurface snapshot.
#include "haptics/snapshot_depth.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "haptics/convex_contact.hpp"

namespace tridex::haptics::contact {

bool window_ok(const ActiveSurface::Window& w) {
    return w.nu >= 2 && w.nv >= 2 && w.nu <= ActiveSurface::kWindow && w.nv <= ActiveSurface::kWindow && w.stride >= 1;
}

// Largest window ray spacing over the usable windows of `s`, m: the lateral resolution of the snapshot.
double spacing_m(const ActiveSurface& s) {
    int cells = 1;
    for (int a = 0; a < 3; ++a)
        if (window_ok(s.sets[a])) cells = std::max(cells, s.window_spacing_cells(a));
    return cells * s.cell_m;
}

// Signed distance (grid units) along ray (iu, iv) from depth d to the nearest interval end: positive
// inside an interval, negative outside; -kEmpty for an empty ray.
double ray_signed_depth(const ActiveSurface::Window& w, int iu, int iv, double d) {
    const int c = std::min(w.intervals(iu, iv), ActiveSurface::kMaxIntervals);
    double best = -kEmpty;
    for (int i = 0; i < c; ++i) best = std::max(best, std::min(d - w.enter(iu, iv, i), w.exit(iu, iv, i) - d));
    return best;
}

// Readings as DepthReading describes (header); sets whose four rays differ by more than kBlendSpreadCells
// spacings straddle an edge and do not blend.
constexpr double kBlendSpreadCells = 2.0;
DepthReading read_depth(const ActiveSurface& s, const Vec3& p) {
    DepthReading r;
    double blended = kEmpty;
    for (int a = 0; a < 3; ++a) {
        const ActiveSurface::Window& w = s.sets[a];
        if (!window_ok(w)) continue;
        const ActiveSurface::WindowCoord c = s.to_window(a, p);
        const double fu = c.fu, fv = c.fv;
        if (!(fu >= 0.0 && fu <= w.nu - 1 && fv >= 0.0 && fv <= w.nv - 1)) continue;
        const int iu = std::min(static_cast<int>(fu), w.nu - 2);
        const int iv = std::min(static_cast<int>(fv), w.nv - 2);
        const double c00 = ray_signed_depth(w, iu, iv, c.d), c10 = ray_signed_depth(w, iu + 1, iv, c.d);
        const double c01 = ray_signed_depth(w, iu, iv + 1, c.d), c11 = ray_signed_depth(w, iu + 1, iv + 1, c.d);
        const double lo = std::min(std::min(c00, c10), std::min(c01, c11));
        const double hi = std::max(std::max(c00, c10), std::max(c01, c11));
        if (lo <= -kEmpty) continue;  // an empty ray: this set vouches for nothing and does not blend
        const double per = 1.0 / s.window_spacing_cells(a);  // grid units -> ray spacings
        r.vouched = std::max(r.vouched, per * lo);
        if (per * (hi - lo) > kBlendSpreadCells) continue;
        const double su = fu - iu, sv = fv - iv;
        blended = std::min(blended, per * ((1.0 - sv) * ((1.0 - su) * c00 + su * c10) + sv * ((1.0 - su) * c01 + su * c11)));
    }
    if (blended < kEmpty) r.blended = blended;
    return r;
}

// The guard's test: inside when either reading says deeper than kGuardMarginCells.
bool inside_material(const ActiveSurface& s, const Vec3& p) {
    const DepthReading r = read_depth(s, p);
    return r.vouched > kGuardMarginCells || r.blended > kGuardMarginCells;
}

bool touches_material(const ActiveSurface& s, const Vec3& p) {
    const DepthReading r = read_depth(s, p);
    return r.vouched > 0.0 || r.blended > 0.0;
}

// True when p is clearly out of material: at least one ray set's window covers it, and in every set that does, each
// of the four rays around its projection has it more than kFreeMarginCells window spacings outside its intervals.
bool clearly_outside(const ActiveSurface& s, const Vec3& p) {
    bool covered = false;
    for (int a = 0; a < 3; ++a) {
        const ActiveSurface::Window& w = s.sets[a];
        if (!window_ok(w)) continue;
        const ActiveSurface::WindowCoord c = s.to_window(a, p);
        if (!(c.fu >= 0.0 && c.fu <= w.nu - 1 && c.fv >= 0.0 && c.fv <= w.nv - 1)) continue;
        const int iu = std::min(static_cast<int>(c.fu), w.nu - 2);
        const int iv = std::min(static_cast<int>(c.fv), w.nv - 2);
        const double limit = -kFreeMarginCells * s.window_spacing_cells(a);
        for (int k = 0; k < 4; ++k)
            if (ray_signed_depth(w, iu + (k & 1), iv + (k >> 1), c.d) > limit) return false;
        covered = true;
    }
    return covered;
}

// True when the tool at `at` is clearly out of material (clearly_outside): its centre and, for a ball, its six
// points at +-radius along the axes.
bool tool_clearly_free(const ActiveSurface& s, const Vec3& at, double radius) {
    if (!clearly_outside(s, at)) return false;
    for (int i = 0; i < 6 && radius > 0.0; ++i) {
        Vec3 p = at;
        p[i >> 1] += (i & 1) ? -radius : radius;
        if (!clearly_outside(s, p)) return false;
    }
    return true;
}

bool covers(const ActiveSurface& s, const Vec3& p) {
    bool any = false;
    for (int a = 0; a < 3; ++a) {
        const ActiveSurface::Window& w = s.sets[a];
        if (!window_ok(w)) continue;
        const ActiveSurface::WindowCoord c = s.to_window(a, p);
        if (!(c.fu >= 0.0 && c.fu <= w.nu - 1 && c.fv >= 0.0 && c.fv <= w.nv - 1)) return false;
        any = true;
    }
    return any;
}

bool pose_free(const ActiveSurface& s, const Vec3& at, double radius, const Vec3& offset, bool with_contact) {
    if (inside_material(s, at)) return false;
    if (radius <= 0.0) return true;
    if (with_contact && inside_material(s, at - offset)) return false;
    for (int i = 0; i < 6; ++i) {
        Vec3 p = at;
        p[i >> 1] += (i & 1) ? -radius : radius;
        if (inside_material(s, p)) return false;
    }
    return true;
}

namespace {
// ball_free: a face this far into the ball (window spacings) still counts as free.
constexpr double kBallTouchCells = 0.25;
}  // namespace

bool ball_free(const ActiveSurface& s, const Vec3& at, double radius) {
    if (inside_material(s, at)) return false;
    if (!(radius > 0.0)) return true;
    bool any = false;
    for (int a = 0; a < 3; ++a) {
        const ActiveSurface::Window& w = s.sets[a];
        if (!window_ok(w)) continue;
        any = true;
        const int ua = (a + 1) % 3, va = (a + 2) % 3;
        const double st = s.window_spacing_cells(a);
        const Vec3 g = (at - s.origin_m) / s.cell_m;
        // A ball that touches a face is free: its radius is taken a quarter spacing short (the guard's margin).
        const double r = std::max(0.0, radius / s.cell_m - kBallTouchCells * st);
        const int iu0 = std::max(0, static_cast<int>(std::ceil((g[ua] - r - w.u0) / st)));
        const int iu1 = std::min(w.nu - 1, static_cast<int>(std::floor((g[ua] + r - w.u0) / st)));
        const int iv0 = std::max(0, static_cast<int>(std::ceil((g[va] - r - w.v0) / st)));
        const int iv1 = std::min(w.nv - 1, static_cast<int>(std::floor((g[va] + r - w.v0) / st)));
        for (int iv = iv0; iv <= iv1; ++iv) {
            for (int iu = iu0; iu <= iu1; ++iu) {
                const std::array<int, 2> uv = s.lattice_ray(a, iu, iv);
                const double du = uv[0] - g[ua], dv = uv[1] - g[va];
                const double h2 = r * r - du * du - dv * dv;
                if (!(h2 > 0.0)) continue;
                const double h = std::sqrt(h2);
                const int n = std::min(w.intervals(iu, iv), ActiveSurface::kMaxIntervals);
                for (int k = 0; k < n; ++k)
                    if (w.enter(iu, iv, k) < g[a] + h && w.exit(iu, iv, k) > g[a] - h) return false;
            }
        }
    }
    return any;
}

namespace {

// The straight path from `from` to `to` keeps the centre out of material, read without the guard's margin every
// quarter spacing (at most 128 samples): a proxy stays on the side of a wall it entered from, however thin.
bool reachable(const ActiveSurface& s, const Vec3& from, const Vec3& to) {
    const double step = 0.25 * spacing_m(s);
    const double len = glm::length(to - from);
    const int n = std::clamp(static_cast<int>(std::ceil(len / step)), 1, 128);
    for (int i = 1; i <= n; ++i)
        if (touches_material(s, from + (to - from) * (static_cast<double>(i) / n))) return false;
    return true;
}

// The offsets of free_centre_on_lattice in lattice steps (x, y, z, squared length), by distance from the centre
// (then lexicographic); built at compile time, so the haptic thread never allocates for them.
using LatticeOffsets = std::array<std::array<int, 4>, kLatticeCandidates>;
constexpr LatticeOffsets make_lattice_offsets() {
    LatticeOffsets v{};
    std::size_t n = 0;
    constexpr int k = kLatticeSteps;
    for (int len2 = 1; len2 <= k * k; ++len2)
        for (int i = -k; i <= k; ++i)
            for (int j = -k; j <= k; ++j)
                for (int l = -k; l <= k; ++l)
                    if (i * i + j * j + l * l == len2) {
                        if (n < v.size()) v[n] = {i, j, l, len2};
                        ++n;
                    }
    return n == v.size() ? v : LatticeOffsets{};
}
constexpr LatticeOffsets kLatticeOffsets = make_lattice_offsets();
static_assert(kLatticeOffsets.back()[3] == kLatticeSteps * kLatticeSteps, "kLatticeCandidates is the lattice's count");

}  // namespace

bool free_centre_on_lattice(const ActiveSurface& s, const Vec3& hip, double radius, const Vec3& from, Vec3& out) {
    if (!(radius > 0.0) || !std::isfinite(radius) || !is_finite(from) || !is_finite(hip)) return false;
    const LatticeOffsets& offsets = kLatticeOffsets;
    const double len = glm::length(from - hip);
    const Vec3 t = len > 0.0 ? (from - hip) / len : Vec3(0.0);
    const double step = radius / kLatticeSteps;
    std::size_t i = 0;
    while (i < offsets.size()) {
        const int shell = offsets[i][3];
        double best = -2.0;
        for (; i < offsets.size() && offsets[i][3] == shell; ++i) {
            const Vec3 d(offsets[i][0], offsets[i][1], offsets[i][2]);
            const Vec3 q = hip + d * step;
            const double along = glm::dot(d, t);
            if (along <= best || !ball_free(s, q, radius) || !reachable(s, from, q)) continue;
            best = along;
            out = q;
        }
        if (best > -2.0) return true;
    }
    return false;
}

bool free_centre_within_radius(const ActiveSurface& s, const Vec3& hip, double radius, const Vec3& from, Vec3& out,
                               bool lattice) {
    if (!(radius > 0.0) || !std::isfinite(radius) || !is_finite(from)) return false;
    if (ball_free(s, hip, radius) && reachable(s, from, hip)) {
        out = hip;
        return true;
    }
    const double len = glm::length(from - hip);
    const Vec3 t = len > 0.0 ? (from - hip) / len : Vec3(0.0);
    // One radius out first: where something is free there, the nearer rings are tried; where nothing is, the lattice.
    const auto ring = [&](double f, Vec3& at) {
        double best = -2.0;
        for (const Vec3& d : ball_directions()) {
            const double along = glm::dot(d, t);
            const Vec3 q = hip + f * radius * d;
            if (along <= best || !ball_free(s, q, radius) || !reachable(s, from, q)) continue;
            best = along;
            at = q;
        }
        return best > -2.0;
    };
    Vec3 far(0.0);
    if (!ring(1.0, far)) return lattice && free_centre_on_lattice(s, hip, radius, from, out);
    for (const double f : {0.25, 0.5, 0.75})
        if (ring(f, out)) return true;
    out = far;
    return true;
}

double exit_distance_m(const ActiveSurface& s, const Vec3& p, int axis, int sign) {
    const ActiveSurface::Window& w = s.sets[axis];
    if (!window_ok(w)) return -1.0;
    const ActiveSurface::WindowCoord c = s.to_window(axis, p);
    if (!(c.fu >= 0.0 && c.fu <= w.nu - 1 && c.fv >= 0.0 && c.fv <= w.nv - 1)) return -1.0;
    const int iu = std::min(static_cast<int>(c.fu), w.nu - 2);
    const int iv = std::min(static_cast<int>(c.fv), w.nv - 2);
    double cells = 0.0;
    for (int k = 0; k < 4; ++k) {
        const int u = iu + (k & 1), v = iv + (k >> 1);
        const int n = std::min(w.intervals(u, v), ActiveSurface::kMaxIntervals);
        for (int i = 0; i < n; ++i)
            if (c.d >= w.enter(u, v, i) && c.d <= w.exit(u, v, i))
                cells = std::max(cells, sign > 0 ? w.exit(u, v, i) - c.d : c.d - w.enter(u, v, i));
    }
    return cells * s.cell_m;
}

}  // namespace tridex::haptics::contact
