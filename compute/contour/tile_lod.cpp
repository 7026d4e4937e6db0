// compute/contour/tile_lod.cpp - per-tile levels of detail with meshoptimizer, borders locked, errors estimated
// or bounded.
#include "compute/contour/tile_lod.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <utility>

#include <meshoptimizer.h>

#include "compute/contour/meshopt_scratch.hpp"
#include "compute/contour/surface_distance.hpp"
#include "core/error.hpp"

namespace tridex::compute {
namespace {

constexpr unsigned kNoCopy = ~0u;

std::uint64_t edge_key(unsigned a, unsigned b) { return (std::uint64_t{a} << 32) | b; }

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
    std::vector<std::uint8_t> on_border;           // per vertex: on the open border
    std::vector<std::uint64_t> open;               // open (border) edges, directed (edge_key), ascending
    std::vector<std::uint64_t> border_links;       // edges between two border vertices (edge_key(min, max)), sorted
    std::vector<std::array<unsigned, 3>> fans;     // per border vertex and fan: (vertex, first, last), by vertex
};

// The fans around vertex v from its links (from, to), sorted by from: closed (one cycle through every link) for an
// inner vertex; for a border vertex, one (v, first, last) path per link whose start no link reaches. False when
// the links do not form that shape (a second cycle, or a fan that closes on the border).
bool vertex_fans(unsigned v, std::span<const std::array<unsigned, 2>> links, bool border,
                 std::vector<std::array<unsigned, 3>>& fans) {
    const auto next = [&](unsigned from) -> const std::array<unsigned, 2>* {
        for (const auto& l : links)
            if (l[0] == from) return &l;
        return nullptr;
    };
    std::size_t walked = 0;
    if (!border) {
        unsigned at = links.front()[0];
        do {
            const auto* l = next(at);
            if (!l) break;
            at = (*l)[1];
            ++walked;
        } while (at != links.front()[0] && walked <= links.size());
    } else {
        for (const auto& start : links) {
            const bool reached = std::any_of(links.begin(), links.end(), [&](const auto& l) { return l[1] == start[0]; });
            if (reached) continue;  // not the start of a fan
            unsigned at = start[0];
            for (const auto* l = next(at); l && walked <= links.size(); l = next(at)) {
                at = (*l)[1];
                ++walked;
            }
            fans.push_back({v, start[0], at});
        }
    }
    return walked == links.size();
}

// The shape of `indices` (a triangle list over nv vertices) with `on_border` given (empty: computed). Each
// triangle (v, a, b) links a -> b at v (and has the directed edge v -> a); the links are bucketed per vertex
// (counting sort), so the whole shape costs O(T + nv) for T triangles.
BorderShape border_shape(const std::vector<unsigned int>& indices, std::size_t nv, std::vector<std::uint8_t> on_border,
                         bool* manifold = nullptr) {
    BorderShape s;
    bool ok = true;
    std::vector<unsigned> start(nv + 1, 0);
    for (const unsigned v : indices) ++start[v + 1];
    for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
    std::vector<std::array<unsigned, 2>> links(indices.size());
    {
        std::vector<unsigned> fill(start.begin(), start.end() - 1);
        for (std::size_t i = 0; i < indices.size(); i += 3)
            for (int k = 0; k < 3; ++k) links[fill[indices[i + k]]++] = {indices[i + (k + 1) % 3], indices[i + (k + 2) % 3]};
    }
    const auto links_of = [&](unsigned v) {
        return std::span<std::array<unsigned, 2>>(links.data() + start[v], start[v + 1] - start[v]);
    };
    const auto has_edge = [&](unsigned a, unsigned b) {  // the directed edge a -> b
        for (const auto& l : links_of(a))
            if (l[0] == b) return true;
        return false;
    };
    for (unsigned v = 0; v < nv; ++v) {
        const auto mine = links_of(v);
        std::sort(mine.begin(), mine.end());
        for (std::size_t k = 0; k < mine.size(); ++k) {
            if (k > 0 && mine[k][0] == mine[k - 1][0]) ok = false;  // the edge v -> from used twice one way
            if (!has_edge(mine[k][0], v)) s.open.push_back(edge_key(v, mine[k][0]));
        }
    }
    if (on_border.empty()) {
        on_border.assign(nv, 0);
        for (const std::uint64_t e : s.open) on_border[e >> 32] = on_border[e & 0xffffffffu] = 1;
    }
    for (unsigned v = 0; v < nv; ++v) {
        if (!on_border[v]) continue;
        for (const auto& l : links_of(v))
            if (on_border[l[0]]) s.border_links.push_back(edge_key(std::min(v, l[0]), std::max(v, l[0])));
    }
    std::sort(s.border_links.begin(), s.border_links.end());
    s.border_links.erase(std::unique(s.border_links.begin(), s.border_links.end()), s.border_links.end());
    // Inside the tile a vertex's links form one cycle; on the border they form paths, one per fan, from one
    // border edge to another.
    for (unsigned v = 0; v < nv; ++v)
        if (start[v + 1] > start[v] && !vertex_fans(v, links_of(v), on_border[v] != 0, s.fans)) ok = false;
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
// border vertex, so no border vertex ever gains an edge to another. meshoptimizer stops at `target` (relative
// error) or once `keep` triangles are left in all (0: only at the error). Result in full-mesh
// indices (empty when meshoptimizer gave nothing); `error` gets meshoptimizer's error estimate, relative to the
// mesh's extent.
std::vector<unsigned int> simplify_cut(const std::vector<unsigned int>& prev, const std::vector<float>& xyz,
                                       const std::vector<std::uint8_t>& on_border, float target, std::size_t keep,
                                       bool seam, float& error) {
    const std::size_t nv = on_border.size();
    std::vector<unsigned int> strip, rest;
    for (std::size_t i = 0; i < prev.size(); i += 3) {
        const bool touches = on_border[prev[i]] || on_border[prev[i + 1]] || on_border[prev[i + 2]];
        (touches ? strip : rest).insert((touches ? strip : rest).end(), prev.begin() + i, prev.begin() + i + 3);
    }
    std::vector<unsigned int> out(prev.size());
    error = 0.0f;
    if (!seam) {  // the strip as it is, the rest simplified with its own border locked
        const std::size_t rest_keep = 3 * keep > strip.size() ? 3 * keep - strip.size() : 0;
        const std::size_t count = meshopt_simplify(out.data(), rest.data(), rest.size(), xyz.data(), nv,
                                                   sizeof(float) * 3, rest_keep, target, meshopt_SimplifyLockBorder, &error);
        out.resize(count);
        out.insert(out.begin(), strip.begin(), strip.end());
        return out;
    }
    std::vector<float> ext = xyz;
    std::vector<unsigned int> copy_of;          // copy index - nv -> original
    std::vector<unsigned int> copy(nv, kNoCopy);  // original -> copy index
    for (unsigned int& v : strip) {
        if (on_border[v]) continue;
        if (copy[v] == kNoCopy) {
            copy[v] = static_cast<unsigned>(nv + copy_of.size());
            copy_of.push_back(v);
            ext.insert(ext.end(), xyz.begin() + 3 * v, xyz.begin() + 3 * v + 3);
        }
        v = copy[v];
    }
    std::vector<unsigned int> all = strip;
    all.insert(all.end(), rest.begin(), rest.end());
    const std::size_t count = meshopt_simplify(out.data(), all.data(), all.size(), ext.data(), ext.size() / 3,
                                               sizeof(float) * 3, 3 * keep, target, meshopt_SimplifyLockBorder, &error);
    out.resize(count);
    for (unsigned int& v : out)
        if (v >= nv) v = copy_of[v - nv];
    return out;
}

void check_options(const TileLodOptions& o, double base_error_m) {
    if (!std::isfinite(o.cell_m) || !(o.cell_m > 0.0))
        throw Error("build_tile_lod: cell_m must be finite and > 0, got " + std::to_string(o.cell_m));
    for (std::size_t k = 0; k < o.error_cells.size(); ++k)
        if (!std::isfinite(o.error_cells[k]) || !(o.error_cells[k] > 0.0) || (k > 0 && !(o.error_cells[k] > o.error_cells[k - 1])))
            throw Error("build_tile_lod: error_cells must be positive and ascending (entry " + std::to_string(k) + ")");
    if (!(o.keep_fraction > 0.0 && o.keep_fraction < 1.0))
        throw Error("build_tile_lod: keep_fraction must lie in (0, 1)");
    if (!std::isfinite(o.sample_spacing_cells) || !(o.sample_spacing_cells > 0.0))
        throw Error("build_tile_lod: sample_spacing_cells must be finite and > 0");
    if (!std::isfinite(o.estimate_factor) || !(o.estimate_factor >= 1.0))
        throw Error("build_tile_lod: estimate_factor must be finite and >= 1");
    if (!std::isfinite(base_error_m) || base_error_m < 0.0)
        throw Error("build_tile_lod: base_error_m must be finite and >= 0");
}

// The sampled two-sided distance bound of build_lod_levels' kSampledBound (TileLodLevel::error_m).
struct SampledBound {
    SampledBound(const TriMesh& mesh, const TileLodOptions& o)
        : spacing(o.sample_spacing_cells * o.cell_m), full_samples(surface_samples(mesh, spacing)), full_grid(mesh, o.cell_m),
          cell_m(o.cell_m) {}
    double operator()(const TriMesh& level) {
        TriangleGrid level_grid(level, cell_m);
        const double to_level = max_distance(full_samples, level_grid);
        const double to_full = max_distance(surface_samples(level, spacing), full_grid);
        return std::max(to_level, to_full) + spacing / std::sqrt(3.0);
    }
    double spacing;
    std::vector<Vec3> full_samples;
    TriangleGrid full_grid;
    double cell_m;
};

}  // namespace

void order_for_vertex_cache(TriMesh& mesh) {
    (void)meshopt_scratch_installed();
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
    check_options(o, base_error_m);
    (void)meshopt_scratch_installed();
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
    std::unique_ptr<SampledBound> bound;
    if (o.measure == LodErrorMeasure::kSampledBound) bound = std::make_unique<SampledBound>(mesh, o);

    // Each level from the previous one by simplify_cut: with the seam first; when that level does not keep the
    // border (keeps_border), with the strip kept whole; when neither does, the probe below if it keeps the
    // border, else no coarser levels. Its target: a
    // probe asks meshoptimizer for keep_fraction of the triangles within the largest target; the error that
    // took picks the first target that can get there (so the targets below it cost nothing), and the level is
    // simplified as far as that target allows. A target counts base_error_m and the estimates of the
    // simplifications before (which add up). A level at no more error than the one before replaces it (a flat
    // face: every step at no error).
    const BorderShape full_shape = border_shape(indices, nv, {});
    std::vector<unsigned int> prev = indices, all;
    double prev_estimate_m = 0.0;  // of the previous kept level to `mesh`, m
    const double factor = bound ? 1.0 : o.estimate_factor;
    const auto room_m = [&](std::size_t k) { return (o.error_cells[k] * o.cell_m - base_error_m) / factor - prev_estimate_m; };
    for (std::size_t k = 0; k < o.error_cells.size(); ++k) {
        const std::size_t last = o.error_cells.size() - 1;
        if (!(room_m(last) > 0.0)) break;
        const auto limit = static_cast<std::size_t>(o.keep_fraction * static_cast<double>(prev.size() / 3));
        float probe_error = 0.0f, step_error = 0.0f;
        const std::vector<unsigned int> probe =
            simplify_cut(prev, xyz, full_shape.on_border, static_cast<float>(room_m(last) / scale), limit, true, probe_error);
        if (probe.empty() || probe.size() / 3 > limit) break;  // not even the largest target gets there
        while (k < last && room_m(k) < static_cast<double>(probe_error) * scale) ++k;
        if (!(room_m(k) > 0.0)) continue;
        bool kept = false;
        for (const bool seam : {true, false}) {
            all = simplify_cut(prev, xyz, full_shape.on_border, static_cast<float>(room_m(k) / scale), 0, seam, step_error);
            if (!all.empty() && keeps_border(all, full_shape)) {
                kept = true;
                break;
            }
        }
        if (!kept && keeps_border(probe, full_shape)) {  // the gentler probe as the level
            all = probe;
            step_error = probe_error;
            kept = true;
        }
        if (!kept) break;
        if (all.size() / 3 > limit) continue;
        TileLodLevel level = compact_level(mesh, materials, normals, all);
        const double estimate_m = prev_estimate_m + static_cast<double>(step_error) * scale;
        level.error_m = (bound ? (*bound)(level.mesh) : factor * estimate_m) + base_error_m;
        if (!levels.empty() && level.error_m <= levels.back().error_m) levels.pop_back();
        levels.push_back(std::move(level));
        prev = all;
        prev_estimate_m = estimate_m;
    }
    return levels;
}

}  // namespace tridex::compute
