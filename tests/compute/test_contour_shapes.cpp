// Tests of compute/contour_dual on analytic models: a sphere and a box with exact chords on every ray.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "compute/contour_dual.hpp"
#include "core/error.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;

struct Distances {
    double max_cells = 0.0;
    double mean_cells = 0.0;
};

/// Distance of every mesh vertex to the analytic surface, in cells, from a signed-distance function
/// (grid units).
template <class Sdf>
Distances vertex_distances(const TriMesh& m, const Lattice& l, Sdf sdf) {
    Distances d;
    for (const Vec3& p : m.positions) {
        const double e = std::abs(sdf(l.to_grid(p)));
        d.max_cells = std::max(d.max_cells, e);
        d.mean_cells += e;
    }
    d.mean_cells /= static_cast<double>(m.positions.size());
    return d;
}

struct SphereRun {
    TriMesh mesh;
    ContourStats stats;
    Distances dist;
    double volume_rel_error = 0.0;
    double update_seconds = 0.0;  ///< update() of all tiles
    double mesh_seconds = 0.0;    ///< mesh() assembly
};

SphereRun contour_sphere(int cells, const Vec3& c, double r) {
    const Lattice l = cube_lattice(cells);
    TriDexel model = empty_model(l);
    fill_rays(model, [&](int a, int u, int v) { return sphere_chord(c, r, a, u, v); });
    Contourer contourer(model);
    SphereRun run;
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_EQ(contourer.update(model), model.tiles.count());
    const auto t1 = std::chrono::steady_clock::now();
    run.mesh = contourer.mesh();
    run.update_seconds = std::chrono::duration<double>(t1 - t0).count();
    run.mesh_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    run.stats = contourer.stats();
    run.dist = vertex_distances(run.mesh, l, [&](const Vec3& g) { return glm::length(g - c) - r; });
    const double exact = 4.0 / 3.0 * M_PI * std::pow(r * l.cell_m, 3);
    run.volume_rel_error = (signed_volume(run.mesh) - exact) / exact;
    for (std::uint8_t d : model.tiles.dirty) EXPECT_EQ(d, 0);  // update() cleared the dirty flags
    return run;
}

void report(const char* name, const SphereRun& s) {
    std::printf("%s: %zu vertices, %zu triangles, vertex distance max %.4f mean %.4f cells, volume error %.3e, "
                "cells visited %zu, fallbacks %zu, split faces %zu, update %.3f s, mesh %.3f s\n",
                name, s.stats.vertices, s.stats.triangles, s.dist.max_cells, s.dist.mean_cells, s.volume_rel_error,
                s.stats.cells_visited, s.stats.fallbacks, s.stats.split_faces, s.update_seconds,
                s.mesh_seconds);
}

TEST(ContourSphere, ClosedAccurateAndCloseInVolume) {
    const SphereRun s = contour_sphere(64, Vec3(31.7, 32.2, 30.9), 25.3);
    report("sphere N=64 r=25.3", s);
    expect_closed_manifold(s.mesh);
    EXPECT_EQ(s.stats.triangles, s.mesh.triangles.size());
    // Every vertex within one cell diagonal of the sphere; the mass point of crossings on a sphere of
    // radius 25 cells lies much closer (measured max ~0.03 cells), so also bound it at 0.1 cells.
    EXPECT_LE(s.dist.max_cells, std::sqrt(3.0));
    EXPECT_LE(s.dist.max_cells, 0.1);
    // Enclosed volume within 0.5 % of 4/3 pi r^3 (facets and mass points sit slightly inside).
    EXPECT_LT(std::abs(s.volume_rel_error), 5e-3);
    // Genus 0: V - E + F = 2 with E = 3F/2.
    EXPECT_EQ(static_cast<long>(s.mesh.positions.size()) - static_cast<long>(3 * s.mesh.triangles.size() / 2) +
                  static_cast<long>(s.mesh.triangles.size()),
              2);
    // Only surface cells are visited: a sphere of radius 25 cells crosses about 4 pi r^2 * 1.5 cells.
    EXPECT_LT(s.stats.cells_visited, static_cast<std::size_t>(4.0 * M_PI * 25.3 * 25.3 * 2.0));
}

TEST(ContourSphere, Resolution256FromScratch) {
    const SphereRun s = contour_sphere(256, Vec3(127.6, 128.3, 128.1), 0.4 * 256);
    report("sphere N=256 r=102.4", s);
    RecordProperty("update_seconds", std::to_string(s.update_seconds));
    RecordProperty("mesh_seconds", std::to_string(s.mesh_seconds));
    expect_closed_manifold(s.mesh);
    EXPECT_LE(s.dist.max_cells, 0.1);
    EXPECT_LT(std::abs(s.volume_rel_error), 1e-3);
}

TEST(ContourBox, ClosedAccurateAndCloseInVolume) {
    const Lattice l = cube_lattice(48);
    TriDexel model = empty_model(l);
    const Vec3 lo(10.3, 12.6, 9.2), hi(40.7, 30.1, 37.55);
    fill_rays(model, [&](int a, int u, int v) { return box_chord(lo, hi, a, u, v); });
    Contourer contourer(model);
    contourer.update(model);
    const TriMesh m = contourer.mesh();
    expect_closed_manifold(m);
    const auto box_sdf = [&](const Vec3& g) {
        const Vec3 q = glm::max(lo - g, g - hi);  // per axis: > 0 outside that slab
        const double out = glm::length(glm::max(q, Vec3(0.0)));
        return out > 0.0 ? out : std::max({q.x, q.y, q.z});
    };
    const Distances d = vertex_distances(m, l, box_sdf);
    const Vec3 size = (hi - lo) * l.cell_m;
    const double exact = size.x * size.y * size.z;
    const double rel = (signed_volume(m) - exact) / exact;
    std::printf("box: %zu triangles, vertex distance max %.4f mean %.4f cells, volume error %.3e\n",
                m.triangles.size(), d.max_cells, d.mean_cells, rel);
    // Flat faces are exact; vertices in cells on the box's edges and corners sit at the mean of crossings
    // on two or three faces, at most 1/sqrt(2) cell (edge) from the surface.
    EXPECT_LE(d.max_cells, std::sqrt(3.0));
    EXPECT_LE(d.max_cells, std::sqrt(0.5) + 1e-9);
    // Rounded edges lose a sliver along the 12 box edges: within 1 % of the volume.
    EXPECT_LT(std::abs(rel), 1e-2);
    EXPECT_LT(rel, 0.0);
}

TEST(Contourer, RejectsAModelOnAnotherLattice) {
    TriDexel a = empty_model(cube_lattice(32)), b = empty_model(cube_lattice(48));
    Contourer contourer(a);
    EXPECT_THROW(contourer.update(b), Error);
    b.sets[1].rays.pop_back();
    Contourer other(b);
    EXPECT_THROW(other.update(b), Error);
    EXPECT_EQ(b.tiles.dirty.front(), 1);  // left unchanged
}

}  // namespace
}  // namespace tridex::compute
