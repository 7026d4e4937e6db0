// compute/contour/distance_grid_build.cpp - exact node distances to a mesh, signed by its scan conversion.
#include "compute/contour/distance_grid_build.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "compute/contour/surface_distance.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/tridexel.hpp"
#include "compute/parallel/task_pool.hpp"
#include "core/error.hpp"
#include "core/format.hpp"

namespace tridex::compute {

namespace {

double triangle_distance(const TriMesh& m, std::int32_t t, const Vec3& p) {
    const auto& tri = m.triangles[static_cast<std::size_t>(t)];
    return glm::length(p - closest_point_on_triangle(p, m.positions[tri[0]], m.positions[tri[1]], m.positions[tri[2]]));
}

// Moves each node's triangle to a nearer one around its vertices until none around is nearer: the propagated triangle
// can be a neighbour or two away from the nearest one, and over a mesh the distance to a point falls toward its nearest
// triangle. Every node on its own, on every core.
void descend(const TriMesh& m, const DistanceGrid& g, std::vector<std::int32_t>& near, std::vector<float>& dist) {
    std::vector<std::uint32_t> start(m.positions.size() + 1, 0), around;
    for (const auto& t : m.triangles)
        for (std::uint32_t v : t) ++start[v + 1];
    for (std::size_t v = 0; v < m.positions.size(); ++v) start[v + 1] += start[v];
    around.resize(start.back());
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (std::uint32_t v : m.triangles[t]) around[fill[v]++] = static_cast<std::uint32_t>(t);
    const int nx = g.nodes[0], ny = g.nodes[1];
    pool_for(dist.size(), 4096, [&](const Chunk& c) {
        for (std::size_t n = c.first; n < c.last; ++n) {
            if (near[n] < 0) continue;
            const int i = static_cast<int>(n % nx), j = static_cast<int>((n / nx) % ny), k = static_cast<int>(n / nx / ny);
            const Vec3 p = g.origin_m + g.cell_m * Vec3(i, j, k);
            std::int32_t t = near[n];
            double best = triangle_distance(m, t, p);
            for (int walk = 0; walk < 64; ++walk) {
                std::int32_t next = t;
                for (std::uint32_t v : m.triangles[static_cast<std::size_t>(t)])
                    for (std::uint32_t e = start[v]; e < start[v + 1]; ++e) {
                        const std::int32_t u = static_cast<std::int32_t>(around[e]);
                        if (u == t) continue;
                        const double d = triangle_distance(m, u, p);
                        if (d < best) {
                            best = d;
                            next = u;
                        }
                    }
                if (next == t) break;
                t = next;
            }
            near[n] = t;
            dist[n] = static_cast<float>(best);
        }
    });
}

// The unsigned distance of every node to its nearest triangle. Every node within one cell of a triangle's box measures
// that triangle. From there the nearest triangle is carried from node to node (closest-feature propagation, as in
// Bridson's level-set construction): eight sweeps, one per diagonal direction, each node trying the triangles of its
// three upwind neighbours. Then each node walks to a nearer triangle around its triangle's vertices (descend).
std::vector<float> nearest_distances(const TriMesh& m, const DistanceGrid& g) {
    const std::size_t count = static_cast<std::size_t>(g.nodes[0]) * g.nodes[1] * g.nodes[2];
    std::vector<float> dist(count, std::numeric_limits<float>::infinity());
    std::vector<std::int32_t> near(count, -1);
    auto node = [&](int i, int j, int k) { return g.origin_m + g.cell_m * Vec3(i, j, k); };
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        Aabb box;
        for (std::uint32_t v : m.triangles[t]) box.add((m.positions[v] - g.origin_m) / g.cell_m);
        std::array<int, 3> lo{}, hi{};
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::max(0, static_cast<int>(std::floor(box.lo[a])) - 1);
            hi[a] = std::min(g.nodes[a] - 1, static_cast<int>(std::ceil(box.hi[a])) + 1);
        }
        for (int k = lo[2]; k <= hi[2]; ++k)
            for (int j = lo[1]; j <= hi[1]; ++j)
                for (int i = lo[0]; i <= hi[0]; ++i) {
                    const std::size_t n = g.index(i, j, k);
                    const double d = triangle_distance(m, static_cast<std::int32_t>(t), node(i, j, k));
                    if (d < dist[n]) {
                        dist[n] = static_cast<float>(d);
                        near[n] = static_cast<std::int32_t>(t);
                    }
                }
    }
    const std::array<std::ptrdiff_t, 3> step{1, g.nodes[0], static_cast<std::ptrdiff_t>(g.nodes[0]) * g.nodes[1]};
    for (int sweep = 0; sweep < 8; ++sweep) {
        std::array<int, 3> dir{}, first{}, end{};
        for (int a = 0; a < 3; ++a) {
            dir[a] = (sweep >> a) & 1 ? -1 : 1;
            first[a] = dir[a] > 0 ? 1 : g.nodes[a] - 2;
            end[a] = dir[a] > 0 ? g.nodes[a] : -1;
        }
        for (int k = first[2]; k != end[2]; k += dir[2])
            for (int j = first[1]; j != end[1]; j += dir[1])
                for (int i = first[0]; i != end[0]; i += dir[0]) {
                    const std::size_t n = g.index(i, j, k);
                    for (int a = 0; a < 3; ++a) {
                        const std::size_t from = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(n) - dir[a] * step[a]);
                        if (near[from] < 0 || near[from] == near[n]) continue;
                        const double d = triangle_distance(m, near[from], node(i, j, k));
                        if (d < dist[n]) {
                            dist[n] = static_cast<float>(d);
                            near[n] = near[from];
                        }
                    }
                }
    }
    descend(m, g, near, dist);
    return dist;
}

}  // namespace

DistanceGrid build_distance_grid(const TriMesh& mesh_m, double cell_m, double margin_m, std::size_t max_bytes) {
    if (!(std::isfinite(cell_m) && cell_m > 0.0))
        throw Error("distance grid: cell_m must be finite and > 0, got " + format_number(cell_m));
    if (!(std::isfinite(margin_m) && margin_m >= 0.0))
        throw Error("distance grid: margin_m must be finite and >= 0, got " + format_number(margin_m));
    if (mesh_m.triangles.empty()) throw Error("distance grid: the mesh has no triangles");
    for (const Vec3& p : mesh_m.positions)
        if (!is_finite(p)) throw Error("distance grid: the mesh has a vertex that is not finite");
    const Aabb box = mesh_m.bounds();
    DistanceGrid g;
    g.cell_m = cell_m;
    g.origin_m = box.lo - Vec3(margin_m);
    double count = 1.0;
    for (int a = 0; a < 3; ++a) {
        const double cells = std::ceil((box.hi[a] - box.lo[a] + 2.0 * margin_m) / cell_m);
        if (!(cells < 1e6)) throw Error("distance grid: " + format_number(cells) + " cells along one axis");
        g.nodes[a] = static_cast<int>(cells) + 1;
        if (g.nodes[a] < 2) g.nodes[a] = 2;
        count *= g.nodes[a];
    }
    const double need = count * sizeof(float);
    if (need > static_cast<double>(max_bytes))
        throw Error("distance grid: " + std::to_string(g.nodes[0]) + " x " + std::to_string(g.nodes[1]) + " x " +
                    std::to_string(g.nodes[2]) + " nodes at " + format_number(cell_m * 1e3) + " mm would take " +
                    format_fixed(need / 1e6, 1) + " MB" + ", more than the " + format_fixed(static_cast<double>(max_bytes) / 1e6, 1) + " MB" +
                    " allowed; use a coarser grid");
    // The sign: the mesh's solid on a lattice whose nodes are the grid's.
    Lattice lattice;
    lattice.origin_m = g.origin_m;
    lattice.cell_m = cell_m;
    for (int a = 0; a < 3; ++a) lattice.cells[a] = g.nodes[a] - 1;
    TriDexel solid = TriDexel::empty(lattice, max_bytes * 4 + (std::size_t{64} << 20));
    scan_convert(mesh_m, solid, {});
    const std::vector<float> unsigned_m = nearest_distances(mesh_m, g);
    g.distance_m.assign(unsigned_m.size(), 0.0f);
    const int nx = g.nodes[0], ny = g.nodes[1], nz = g.nodes[2];
    pool_for(static_cast<std::size_t>(nx) * ny, 64, [&](const Chunk& c) {
        for (std::size_t r = c.first; r < c.last; ++r) {
            const int i = static_cast<int>(r % nx), j = static_cast<int>(r / nx);
            const std::vector<Interval>& ray = solid.sets[2].ray(i, j);
            std::size_t at = 0;  // the first interval not yet left behind: nodes k rise along the ray
            for (int k = 0; k < nz; ++k) {
                while (at < ray.size() && ray[at].exit <= k) ++at;
                const bool inside = at < ray.size() && ray[at].enter <= k;  // enter <= k < exit
                const std::size_t n = g.index(i, j, k);
                g.distance_m[n] = inside ? -unsigned_m[n] : unsigned_m[n];
            }
        }
    });
    return g;
}

}  // namespace tridex::compute
