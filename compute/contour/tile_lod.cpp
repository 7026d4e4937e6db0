// compute/contour/tile_lod.cpp - per-tile levels of detail with meshoptimizer, borders locked, errors bounded.
#include "compute/contour/tile_lod.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <utility>

#include <meshoptimizer.h>

#include "compute/contour/surface_distance.hpp"
#include "core/error.hpp"

namespace tridex::compute {
namespace {

// The level's triangles (indices into the full mesh) as a compact mesh with the full mesh's attributes: the
// triangles in vertex-cache order, the vertices in order of first use.
TileLodLevel compact_level(const TriMesh& full, std::span<const std::uint8_t> materials, const std::vector<Vec3>& normals,
                           const std::vector<unsigned int>& unordered) {
    std::vector<unsigned int> indices(unordered.size());
    meshopt_optimizeVertexCache(indices.data(), unordered.data(), unordered.size(), full.positions.size());
    TileLodLevel level;
    std::vector<std::uint32_t> remap(full.positions.size(), UINT32_MAX);
    level.mesh.triangles.reserve(indices.size() / 3);
    for (std::size_t i = 0; i < indices.size(); i += 3) {
        std::array<std::uint32_t, 3> t{};
        for (int k = 0; k < 3; ++k) {
            const unsigned int v = indices[i + k];
            if (remap[v] == UINT32_MAX) {
                remap[v] = static_cast<std::uint32_t>(level.mesh.positions.size());
                level.mesh.positions.push_back(full.positions[v]);
                level.normals.push_back(normals[v]);
                if (!materials.empty()) level.materials.push_back(materials[v]);
            }
            t[k] = remap[v];
        }
        level.mesh.triangles.push_back(t);
    }
    return level;
}

// What a level must keep of the tile mesh so that its neighbours, at any level, still meet it edge to edge.
struct BorderShape {
    std::vector<std::uint8_t> on_border;                        // per vertex: on the open border
    std::vector<std::pair<unsigned, unsigned>> open;            // open (border) edges, directed, sorted
    std::set<std::pair<unsigned, unsigned>> border_links;       // edges between two border vertices (min, max)
    std::vector<std::array<unsigned, 3>> fans;                  // per border vertex and fan: (vertex, first, last)
};

// The shape of `indices` (a triangle list over nv vertices) with `on_border` given (empty: computed).
BorderShape border_shape(const std::vector<unsigned int>& indices, std::size_t nv, std::vector<std::uint8_t> on_border,
                         bool* manifold = nullptr) {
    BorderShape s;
    bool ok = true;
    std::map<std::pair<unsigned, unsigned>, int> directed;
    for (std::size_t i = 0; i < indices.size(); i += 3)
        for (int k = 0; k < 3; ++k)
            if (++directed[{indices[i + k], indices[i + (k + 1) % 3]}] > 1) ok = false;
    for (const auto& [e, n] : directed)
        if (!directed.count({e.second, e.first})) s.open.push_back(e);
    if (on_border.empty()) {
        on_border.assign(nv, 0);
        for (const auto& [x, y] : s.open) on_border[x] = on_border[y] = 1;
    }
    for (const auto& [e, n] : directed)
        if (on_border[e.first] && on_border[e.second]) s.border_links.insert({std::min(e.first, e.second), std::max(e.first, e.second)});
    // Fans: at vertex v each triangle (v, a, b) links a -> b. Inside the tile a vertex's links form one cycle; on
    // the border they form paths, one per fan, from one border edge to another.
    std::map<unsigned, std::map<unsigned, unsigned>> fan;
    for (std::size_t i = 0; i < indices.size(); i += 3)
        for (int k = 0; k < 3; ++k)
            fan[indices[i + k]][indices[i + (k + 1) % 3]] = indices[i + (k + 2) % 3];
    for (const auto& [v, links] : fan) {
        std::set<unsigned> targets;
        for (const auto& [from, to] : links) targets.insert(to);
        std::size_t walked = 0;
        if (!on_border[v]) {
            unsigned at = links.begin()->first;
            do {
                const auto it = links.find(at);
                if (it == links.end()) break;
                at = it->second;
                ++walked;
            } while (at != links.begin()->first && walked <= links.size());
        } else {
            for (const auto& [from, to] : links) {
                if (targets.count(from)) continue;  // not the start of a fan
                unsigned at = from;
                for (auto it = links.find(at); it != links.end() && walked <= links.size(); it = links.find(at)) {
                    at = it->second;
                    ++walked;
                }
                s.fans.push_back({v, from, at});
            }
        }
        if (walked != links.size()) ok = false;  // a second cycle, or a fan that closes on the border
    }
    std::sort(s.fans.begin(), s.fans.end());
    s.on_border = std::move(on_border);
    if (manifold) *manifold = ok;
    return s;
}

// True when `indices` keeps `full`'s border: the same open edges, no edge between two border vertices that the
// full mesh lacks, the same fans around border vertices (from the same border edge to the same one), one closed
// fan around every other vertex, and no edge used twice in one direction.
bool keeps_border(const std::vector<unsigned int>& indices, const BorderShape& full) {
    bool manifold = false;
    const BorderShape s = border_shape(indices, full.on_border.size(), full.on_border, &manifold);
    if (!manifold || s.open != full.open || s.fans != full.fans) return false;
    return std::includes(full.border_links.begin(), full.border_links.end(), s.border_links.begin(), s.border_links.end());
}

// One simplification of `prev` (a level, indices into the full mesh's vertices) with the tile's border kept.
// The border strip (triangles touching a border vertex) is cut from the rest: its vertices that are not on the
// border get copies (at the same positions) in the strip, so meshoptimizer sees a seam there. Border vertices are
// locked (meshopt_SimplifyLockBorder), seam vertices only slide along the seam, and nothing collapses onto a
// border vertex, so no border vertex ever gains an edge to another. Result in full-mesh indices; empty when
// meshoptimizer gave nothing.
std::vector<unsigned int> simplify_cut(const std::vector<unsigned int>& prev, const std::vector<float>& xyz,
                                       const std::vector<std::uint8_t>& on_border, float target, bool seam) {
    const std::size_t nv = on_border.size();
    std::vector<unsigned int> strip, rest;
    for (std::size_t i = 0; i < prev.size(); i += 3) {
        const bool touches = on_border[prev[i]] || on_border[prev[i + 1]] || on_border[prev[i + 2]];
        (touches ? strip : rest).insert((touches ? strip : rest).end(), prev.begin() + i, prev.begin() + i + 3);
    }
    std::vector<unsigned int> out(prev.size());
    if (!seam) {  // the strip as it is, the rest simplified with its own border locked
        const std::size_t count = meshopt_simplify(out.data(), rest.data(), rest.size(), xyz.data(), nv,
                                                   sizeof(float) * 3, 0, target, meshopt_SimplifyLockBorder, nullptr);
        out.resize(count);
        out.insert(out.begin(), strip.begin(), strip.end());
        return out;
    }
    std::vector<float> ext = xyz;
    std::vector<unsigned int> copy_of;  // copy index - nv -> original
    std::map<unsigned, unsigned> copy;
    for (unsigned int& v : strip) {
        if (on_border[v]) continue;
        const auto [it, fresh] = copy.try_emplace(v, static_cast<unsigned>(nv + copy_of.size()));
        if (fresh) {
            copy_of.push_back(v);
            ext.insert(ext.end(), xyz.begin() + 3 * v, xyz.begin() + 3 * v + 3);
        }
        v = it->second;
    }
    std::vector<unsigned int> all = strip;
    all.insert(all.end(), rest.begin(), rest.end());
    const std::size_t count = meshopt_simplify(out.data(), all.data(), all.size(), ext.data(), ext.size() / 3,
                                               sizeof(float) * 3, 0, target, meshopt_SimplifyLockBorder, nullptr);
    out.resize(count);
    for (unsigned int& v : out)
        if (v >= nv) v = copy_of[v - nv];
    return out;
}

}  // namespace

void order_for_vertex_cache(TriMesh& mesh) {
    const std::size_t nv = mesh.positions.size();
    std::vector<unsigned int> in, out(mesh.triangles.size() * 3);
    in.reserve(out.size());
    for (const auto& t : mesh.triangles)
        for (const std::uint32_t v : t) {
            if (v >= nv) throw Error("order_for_vertex_cache: vertex index " + std::to_string(v) + " >= " + std::to_string(nv));
            in.push_back(v);
        }
    meshopt_optimizeVertexCache(out.data(), in.data(), in.size(), nv);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) mesh.triangles[t] = {out[3 * t], out[3 * t + 1], out[3 * t + 2]};
}

std::vector<TileLodLevel> build_tile_lod(const TriMesh& mesh, std::span<const std::uint8_t> materials,
                                         const TileLodOptions& o) {
    return build_lod_levels(mesh, materials, {}, 0.0, o);
}

std::vector<TileLodLevel> build_lod_levels(const TriMesh& mesh, std::span<const std::uint8_t> materials,
                                           std::span<const Vec3> given_normals, double base_error_m,
                                           const TileLodOptions& o) {
    if (!std::isfinite(o.cell_m) || !(o.cell_m > 0.0))
        throw Error("build_tile_lod: cell_m must be finite and > 0, got " + std::to_string(o.cell_m));
    for (std::size_t k = 0; k < o.error_cells.size(); ++k)
        if (!std::isfinite(o.error_cells[k]) || !(o.error_cells[k] > 0.0) || (k > 0 && !(o.error_cells[k] > o.error_cells[k - 1])))
            throw Error("build_tile_lod: error_cells must be positive and ascending (entry " + std::to_string(k) + ")");
    if (!std::isfinite(o.sample_spacing_cells) || !(o.sample_spacing_cells > 0.0))
        throw Error("build_tile_lod: sample_spacing_cells must be finite and > 0");
    if (!std::isfinite(base_error_m) || base_error_m < 0.0)
        throw Error("build_tile_lod: base_error_m must be finite and >= 0");
    const std::size_t nv = mesh.positions.size();
    if (!materials.empty() && materials.size() != nv)
        throw Error("build_tile_lod: " + std::to_string(materials.size()) + " materials for " + std::to_string(nv) +
                    " vertices");
    if (!given_normals.empty() && given_normals.size() != nv)
        throw Error("build_tile_lod: " + std::to_string(given_normals.size()) + " normals for " + std::to_string(nv) +
                    " vertices");
    std::vector<unsigned int> indices;
    indices.reserve(mesh.triangles.size() * 3);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (std::uint32_t v : mesh.triangles[t]) {
            if (v >= nv)
                throw Error("build_tile_lod: triangle " + std::to_string(t) + " has vertex index " + std::to_string(v) +
                            " >= " + std::to_string(nv));
            indices.push_back(v);
        }
    std::vector<TileLodLevel> levels;
    if (mesh.triangles.size() < o.min_triangles || o.error_cells.empty()) return levels;

    // meshoptimizer takes float positions: relative to the tile's box centre they keep about 1e-7 of a tile.
    const Vec3 origin = mesh.bounds().centre();
    std::vector<float> xyz(nv * 3);
    for (std::size_t v = 0; v < nv; ++v)
        for (int a = 0; a < 3; ++a) xyz[v * 3 + a] = static_cast<float>(mesh.positions[v][a] - origin[a]);
    const float scale = meshopt_simplifyScale(xyz.data(), nv, sizeof(float) * 3);
    if (!(scale > 0.0f)) return levels;  // every vertex in one point

    const std::vector<Vec3> normals =
        given_normals.empty() ? vertex_normals(mesh) : std::vector<Vec3>(given_normals.begin(), given_normals.end());
    const double spacing = o.sample_spacing_cells * o.cell_m;
    const double slack = spacing / std::sqrt(3.0);
    const std::vector<Vec3> full_samples = surface_samples(mesh, spacing);
    TriangleGrid full_grid(mesh, o.cell_m);

    // Each level from the previous one by simplify_cut: with the seam first; when that level does not keep the
    // border (keeps_border), with the strip kept whole; when neither does, no coarser levels.
    const BorderShape full_shape = border_shape(indices, nv, {});
    std::size_t prev_count = indices.size();
    std::vector<unsigned int> prev = indices, all;
    for (const double target_cells : o.error_cells) {
        const float target = static_cast<float>(target_cells * o.cell_m / scale);
        bool kept = false;
        for (const bool seam : {true, false}) {
            all = simplify_cut(prev, xyz, full_shape.on_border, target, seam);
            if (!all.empty() && keeps_border(all, full_shape)) {
                kept = true;
                break;
            }
        }
        if (!kept) break;
        if (static_cast<double>(all.size()) > o.keep_fraction * static_cast<double>(prev_count)) continue;
        TileLodLevel level = compact_level(mesh, materials, normals, all);
        TriangleGrid level_grid(level.mesh, o.cell_m);
        const double to_level = max_distance(full_samples, level_grid);
        const double to_full = max_distance(surface_samples(level.mesh, spacing), full_grid);
        level.error_m = std::max(to_level, to_full) + slack + base_error_m;
        levels.push_back(std::move(level));
        prev = all;
        prev_count = all.size();
    }
    return levels;
}

}  // namespace tridex::compute
