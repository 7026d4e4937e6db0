// tests/compute/test_gpu_contour_compare.hpp - comparing the GPU contour (GpuContourer, read back) with
// the CPU contour (Contourer::mesh()): vertices, triangles and manifoldness; expect_same_contour() runs
// both contourers on one model and expects the same mesh.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iostream>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/gpu/gpu_contourer.hpp"
#include "core/tri_mesh.hpp"
#include "gpu/context.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute::testing {

using Pos = std::tuple<double, double, double>;
inline Pos key_of(const Vec3& p) { return {p.x, p.y, p.z}; }

/// A triangle as its three positions, rotated so the smallest comes first (orientation kept).
inline std::array<Pos, 3> canonical(const TriMesh& m, const std::array<std::uint32_t, 3>& t) {
    std::array<Pos, 3> p{key_of(m.positions[t[0]]), key_of(m.positions[t[1]]), key_of(m.positions[t[2]])};
    const int first = static_cast<int>(std::min_element(p.begin(), p.end()) - p.begin());
    std::rotate(p.begin(), p.begin() + first, p.end());
    return p;
}

/// Welds vertices with bit-identical positions (the GPU mesh holds one copy per tile of shared vertices)
/// and drops unreferenced ones (a tile region may hold components no triangle of that tile uses).
inline TriMesh weld_exact(const TriMesh& m) {
    TriMesh out;
    std::map<Pos, std::uint32_t> index;
    for (const auto& t : m.triangles) {
        std::array<std::uint32_t, 3> r{};
        for (int k = 0; k < 3; ++k) {
            const auto [it, fresh] = index.emplace(key_of(m.positions[t[k]]), static_cast<std::uint32_t>(out.positions.size()));
            if (fresh) out.positions.push_back(m.positions[t[k]]);
            r[k] = it->second;
        }
        out.triangles.push_back(r);
    }
    return out;
}

/// What compare_meshes() found.
struct MeshDiff {
    std::size_t cpu_vertices = 0, gpu_vertices = 0;     ///< distinct positions
    std::size_t cpu_triangles = 0, gpu_triangles = 0;
    std::size_t vertices_only_one_side = 0;             ///< positions (with material) in one mesh only
    std::size_t triangles_only_one_side = 0;            ///< triangles (oriented, by positions) in one mesh only
    double max_float_error = 0.0;                       ///< |float - double| of drawn vertices, grid units
    double max_float_bound_ratio = 0.0;                 ///< that error over 2^-24 * |coordinate| (<= 1 expected)
    ContourStats cpu_stats;                             ///< the CPU contourer's (expect_same_contour; QEF branches)
};

/// Compares the GPU contour with the CPU one: positions (and materials) as sets, exactly; triangles as
/// multisets of oriented position triples, exactly; the drawn float vertices against the doubles.
inline MeshDiff compare_meshes(const GpuContourer& gpu, const Contourer& cpu) {
    MeshDiff d;
    const TriMesh c = cpu.mesh();
    const std::vector<std::uint8_t> cm = cpu.mesh_materials();
    std::vector<std::uint8_t> gm;
    const TriMesh g = gpu.download(&gm);
    std::map<Pos, int> vset;  // +1 cpu, +2 gpu
    std::map<std::pair<Pos, int>, int> vmat;
    for (std::size_t i = 0; i < c.positions.size(); ++i) {
        vset[key_of(c.positions[i])] |= 1;
        vmat[{key_of(c.positions[i]), cm[i]}] |= 1;
    }
    std::map<Pos, bool> used;
    for (const auto& t : g.triangles)
        for (const std::uint32_t v : t) used[key_of(g.positions[v])] = true;
    for (std::size_t i = 0; i < g.positions.size(); ++i) {
        if (!used.count(key_of(g.positions[i]))) continue;  // a tile region may hold unreferenced vertices
        vset[key_of(g.positions[i])] |= 2;
        vmat[{key_of(g.positions[i]), gm[i]}] |= 2;
    }
    for (const auto& [p, s] : vset) {
        d.cpu_vertices += (s & 1) ? 1 : 0;
        d.gpu_vertices += (s & 2) ? 1 : 0;
    }
    for (const auto& [p, s] : vmat) d.vertices_only_one_side += s != 3 ? 1 : 0;
    std::map<std::array<Pos, 3>, long> tris;
    for (const auto& t : c.triangles) ++tris[canonical(c, t)];
    for (const auto& t : g.triangles) --tris[canonical(g, t)];
    for (const auto& [t, n] : tris) d.triangles_only_one_side += static_cast<std::size_t>(std::labs(n));
    d.cpu_triangles = c.triangles.size();
    d.gpu_triangles = g.triangles.size();
    // Drawn float vertices against the kernel's doubles (grid units).
    std::vector<GpuContourVertex> fv;
    std::vector<std::array<std::uint32_t, 3>> ft;
    std::vector<Vec3> dv;
    for (std::size_t t = 0; t < gpu.tile_count(); ++t) {
        if (gpu.tile_index_count(t) == 0) continue;
        gpu.download_tile(t, fv, ft, &dv);
        for (std::size_t i = 0; i < fv.size(); ++i)
            for (int k = 0; k < 3; ++k) {
                const double err = std::fabs(static_cast<double>(fv[i].grid[k]) - dv[i][k]);
                d.max_float_error = std::max(d.max_float_error, err);
                if (err > 0.0) d.max_float_bound_ratio = std::max(d.max_float_bound_ratio, err / (std::ldexp(1.0, -24) * std::fabs(dv[i][k])));
            }
    }
    return d;
}

/// Contours `model` (all dirty tiles) on both paths and expects the same closed 2-manifold mesh.
/// Returns the comparison; `label` names the case in messages and the printed line. `inspect`, when
/// given, is called with the GPU contourer afterwards (for checks of its mesh without contouring again).
inline MeshDiff expect_same_contour(const gpu::Context& ctx, TriDexel& model, const std::string& label, GpuContourStats* stats = nullptr,
                                    const std::function<void(const GpuContourer&)>& inspect = {}) {
    const GpuDexelSlabs slabs = GpuDexelSlabs::upload(ctx, model);
    GpuContourer gpu(ctx, slabs, model.lattice, 256, 1024);  // small pools: the grow path runs
    gpu.update_dirty(model.tiles);
    Contourer cpu(model);
    cpu.update(model);
    MeshDiff d = compare_meshes(gpu, cpu);
    d.cpu_stats = cpu.stats();
    EXPECT_GT(d.cpu_triangles, 0u) << label;
    EXPECT_EQ(d.vertices_only_one_side, 0u) << label;
    EXPECT_EQ(d.triangles_only_one_side, 0u) << label;
    EXPECT_EQ(d.cpu_vertices, d.gpu_vertices) << label;
    EXPECT_EQ(d.cpu_triangles, d.gpu_triangles) << label;
    EXPECT_LE(d.max_float_bound_ratio, 1.0) << label;
    // Welded by exact position, the GPU mesh is a closed, consistently oriented 2-manifold, when the CPU
    // mesh has no two vertices at one position (then welding by position is welding by vertex). Rays that
    // disagree with the occupancy can clamp two crossings' means to one point; for those models the
    // exact multiset equality with the CPU mesh above stands for the check.
    if (d.cpu_vertices == cpu.stats().vertices) expect_closed_manifold(weld_exact(gpu.download()));
    else std::cout << "[ gpu contour ] " << label << ": " << cpu.stats().vertices - d.cpu_vertices
                   << " CPU vertices share a position with another; manifold check by position skipped\n";
    std::cout << "[ gpu contour ] " << label << ": " << d.gpu_triangles << " triangles, " << d.gpu_vertices
              << " vertices, split faces on the GPU " << gpu.stats().split_faces_gpu << ", host-contoured tiles " << gpu.stats().tiles_cpu << " of "
              << gpu.stats().tiles_cpu + gpu.stats().tiles_gpu << ", region retries " << gpu.stats().region_retries
              << ", pool grows " << gpu.stats().pool_grows << ", max float error " << d.max_float_error << " cells; CPU QEF vertices "
              << cpu.stats().qef_vertices << " (truncated " << cpu.stats().qef_truncated << ", clamped " << cpu.stats().qef_clamped
              << ", rejected " << cpu.stats().qef_rejected << ")\n";
    if (stats) *stats = gpu.stats();
    if (inspect) inspect(gpu);
    return d;
}

}  // namespace tridex::compute::testing
