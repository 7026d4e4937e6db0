// compute/mesh/scan_convert.cpp - exact ray/triangle crossings on the lattice, winding-number intervals.
#include "compute/mesh/scan_convert.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "compute/parallel/task_pool.hpp"
#include "core/error.hpp"

namespace tridex::compute {
namespace {

using i64 = std::int64_t;
using i128 = __int128;

constexpr i64 kSnap = i64{1} << kSnapBits;  // fixed-point units per cell
constexpr double kMaxGrid = 1099511627776.0;  // 2^40 cells: snapped values stay below 2^56

/// A projected vertex in fixed point (units of 2^-16 cell).
struct P2 {
    i64 u, v;
};

/// Twice the signed area of (a, b, p): > 0 when p is left of a -> b. Exact.
i128 orient(const P2& a, const P2& b, const P2& p) {
    return static_cast<i128>(b.u - a.u) * (p.v - a.v) - static_cast<i128>(b.v - a.v) * (p.u - a.u);
}

/// Sign of orient(a, b, p + (eps, eps^2)) for infinitesimal eps > 0, given o = orient(a, b, p); a != b.
/// The perturbation adds -(b.v - a.v) eps + (b.u - a.u) eps^2, and is never zero for a != b.
int perturbed_sign(i128 o, const P2& a, const P2& b) {
    if (o != 0) return o > 0 ? 1 : -1;
    if (b.v != a.v) return b.v > a.v ? -1 : 1;
    return b.u > a.u ? 1 : -1;
}

/// Smallest integer i with i * kSnap >= x.
i64 ceil_div_snap(i64 x) { return -((-x) >> kSnapBits); }

struct Crossing {
    std::uint32_t ray;  // u + nu * v
    int sign;           // +1 entering (winding up), -1 leaving
    double depth;       // grid units along the ray axis
};

constexpr std::size_t kTriangleChunk = 1024;  // triangles per scan-conversion task
constexpr std::size_t kRayChunk = 4096;       // rays per interval-building task

/// Collects the crossings of triangles [first, last) with the rays of set `ax`, in triangle order.
void rasterise(const std::vector<Vec3>& g, const std::vector<std::array<i64, 3>>& q, const TriMesh& mesh,
               std::size_t first, std::size_t last, const RaySet& set, std::vector<Crossing>& out) {
    const int ax = set.axis, ua = (ax + 1) % 3, va = (ax + 2) % 3;
    for (std::size_t ti = first; ti < last; ++ti) {
        const auto& t = mesh.triangles[ti];
        const P2 a{q[t[0]][ua], q[t[0]][va]}, b{q[t[1]][ua], q[t[1]][va]}, c{q[t[2]][ua], q[t[2]][va]};
        const i128 area2 = orient(a, b, c);
        if (area2 == 0) continue;  // edge-on in this projection
        const int s = area2 > 0 ? 1 : -1;
        const i64 u_first = std::max<i64>(0, ceil_div_snap(std::min({a.u, b.u, c.u})));
        const i64 u_last = std::min<i64>(set.nu - 1, ceil_div_snap(std::max({a.u, b.u, c.u})) - 1);
        const i64 v_first = std::max<i64>(0, ceil_div_snap(std::min({a.v, b.v, c.v})));
        const i64 v_last = std::min<i64>(set.nv - 1, ceil_div_snap(std::max({a.v, b.v, c.v})) - 1);
        const Vec3 &ga = g[t[0]], &gb = g[t[1]], &gc = g[t[2]];
        const double da = ga[ax], db = gb[ax], dc = gc[ax];
        const double d_lo = std::min({da, db, dc}), d_hi = std::max({da, db, dc});
        const double inv_snapped = 1.0 / static_cast<double>(area2);
        // Unsnapped 2D orientation (double), for the depth.
        auto orient_d = [&](const Vec3& p, const Vec3& q, double pu, double pv) {
            return (q[ua] - p[ua]) * (pv - p[va]) - (q[va] - p[va]) * (pu - p[ua]);
        };
        for (i64 v = v_first; v <= v_last; ++v) {
            for (i64 u = u_first; u <= u_last; ++u) {
                const P2 p{u * kSnap, v * kSnap};
                const i128 wa = orient(b, c, p);
                if (perturbed_sign(wa, b, c) != s) continue;
                const i128 wb = orient(c, a, p);
                if (perturbed_sign(wb, c, a) != s) continue;
                const i128 wc = orient(a, b, p);
                if (perturbed_sign(wc, a, b) != s) continue;
                // Depth from the barycentric weights of the unsnapped triangle (accurate to double
                // rounding); when the unsnapped triangle is edge-on or flipped (snapping moved a vertex
                // across), fall back to the exact snapped weights. Clamped to the triangle's depth range.
                const double pu = static_cast<double>(u), pv = static_cast<double>(v);
                const double ra = orient_d(gb, gc, pu, pv), rb = orient_d(gc, ga, pu, pv), rc = orient_d(ga, gb, pu, pv);
                const double sum = ra + rb + rc;
                double depth = (sum > 0.0) == (s > 0) && sum != 0.0
                                   ? (ra * da + rb * db + rc * dc) / sum
                                   : (static_cast<double>(wa) * da + static_cast<double>(wb) * db + static_cast<double>(wc) * dc) * inv_snapped;
                depth = std::clamp(depth, d_lo, d_hi);
                // Outward normal along +ax (s > 0) means the ray leaves the solid here.
                out.push_back({static_cast<std::uint32_t>(u + set.nu * v), -s, depth});
            }
        }
    }
}

/// Appends [enter, exit] (grid units) to a ray after clipping to [0, length], rounding to float,
/// and merging with the previous interval when they touch.
void emit(std::vector<Interval>& ray, double enter, double exit, double length) {
    enter = std::max(enter, 0.0);
    exit = std::min(exit, length);
    const float fe = static_cast<float>(enter), fx = static_cast<float>(exit);
    if (!(fe < fx)) return;
    if (!ray.empty() && fe <= ray.back().exit) {
        ray.back().exit = std::max(ray.back().exit, fx);
        return;
    }
    ray.push_back({fe, fx});
}

/// Turns the crossings of one ray (sorted by depth) into intervals where the winding number is > 0.
void build_ray(const Crossing* first, const Crossing* last, double length, std::vector<Interval>& ray) {
    int winding = 0;
    double enter = 0.0;
    for (const Crossing* c = first; c != last;) {
        const double d = c->depth;
        int delta = 0;
        for (; c != last && c->depth == d; ++c) delta += c->sign;
        const int before = winding;
        winding += delta;
        if (before <= 0 && winding > 0) enter = d;
        else if (before > 0 && winding <= 0) emit(ray, enter, d, length);
    }
}

}  // namespace

void scan_convert(const TriMesh& mesh_m, TriDexel& model, const ProgressFn& progress) {
    if (model.interval_count() != 0) throw Error("scan_convert: the model must be empty (made by TriDexel::empty)");
    const Lattice& L = model.lattice;
    const std::size_t nvert = mesh_m.positions.size();
    for (const auto& t : mesh_m.triangles)
        for (std::uint32_t i : t)
            if (i >= nvert) throw Error("scan_convert: triangle vertex index " + std::to_string(i) + " out of range");
    std::vector<Vec3> g(nvert);
    std::vector<std::array<i64, 3>> q(nvert);
    for (std::size_t i = 0; i < nvert; ++i) {
        if (!is_finite(mesh_m.positions[i])) throw Error("scan_convert: vertex " + std::to_string(i) + " is not finite");
        g[i] = L.to_grid(mesh_m.positions[i]);
        for (int a = 0; a < 3; ++a) {
            if (!(std::abs(g[i][a]) < kMaxGrid)) throw Error("scan_convert: mesh lies too far from the lattice");
            q[i][a] = std::llround(std::ldexp(g[i][a], kSnapBits));
        }
    }
    std::vector<std::vector<Crossing>> parts((mesh_m.triangles.size() + kTriangleChunk - 1) / kTriangleChunk);
    std::vector<Crossing> sorted;
    std::vector<std::size_t> offset;
    for (int ax = 0; ax < 3; ++ax) {
        RaySet& set = model.sets[ax];
        // Triangles in fixed chunks on the task pool; the chunks' crossings, taken in chunk order, are the
        // triangle-ordered list a single thread would make.
        // Progress: each ray set a third, its triangles the first half of it, its rays the second.
        pool_for_progress(
            mesh_m.triangles.size(), kTriangleChunk,
            [&](const Chunk& c) {
                std::vector<Crossing>& part = parts[c.first / kTriangleChunk];
                part.clear();
                rasterise(g, q, mesh_m, c.first, c.last, set, part);
            },
            progress_part(progress, ax / 3.0, (ax + 0.5) / 3.0));
        // Counting sort by ray, then (per ray, on the task pool) a small sort by depth and the intervals.
        offset.assign(set.rays.size() + 1, 0);
        for (const std::vector<Crossing>& part : parts)
            for (const Crossing& c : part) ++offset[c.ray + 1];
        for (std::size_t r = 0; r < set.rays.size(); ++r) offset[r + 1] += offset[r];
        sorted.resize(offset.back());
        {
            std::vector<std::size_t> fill(offset.begin(), offset.end() - 1);
            for (const std::vector<Crossing>& part : parts)
                for (const Crossing& c : part) sorted[fill[c.ray]++] = c;
        }
        const double length = L.cells[ax];
        pool_for_progress(
            set.rays.size(), kRayChunk,
            [&](const Chunk& c) {
                for (std::size_t r = c.first; r < c.last; ++r) {
                    Crossing* first = sorted.data() + offset[r];
                    Crossing* last = sorted.data() + offset[r + 1];
                    if (first == last) continue;
                    std::sort(first, last, [](const Crossing& x, const Crossing& y) { return x.depth < y.depth; });
                    build_ray(first, last, length, set.rays[r]);
                }
            },
            progress_part(progress, (ax + 0.5) / 3.0, (ax + 1.0) / 3.0));
        for (std::size_t r = 0; r < set.rays.size(); ++r) {
            if (offset[r] == offset[r + 1]) continue;
            const int u = static_cast<int>(r % set.nu), v = static_cast<int>(r / set.nu);
            for (const Interval& iv : set.rays[r]) {
                for (float d : {iv.enter, iv.exit}) {
                    Vec3 p;
                    p[ax] = d;
                    p[(ax + 1) % 3] = u;
                    p[(ax + 2) % 3] = v;
                    Aabb box;
                    box.add(L.to_world(p));
                    model.mark_dirty(box);
                }
            }
        }
    }
}

}  // namespace tridex::compute
