// Pieces of material and specks (compute::find_islands) against what the contoured mesh shows: a detached small cube
// is a speck and its rays remove it to the bit; a chunk larger than the threshold, a thin wall and a slanted sheet
// the lattice resolves stay; a sheet thinner than the lattice resolves falls apart into as many pieces as the mesh
// shows; on random cuts the pieces are the mesh's components and removing the specks leaves one.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "compute/contour/contour_dual.hpp"
#include "compute/model/interval_ops.hpp"
#include "compute/model/islands.hpp"
#include "compute/model/volume.hpp"
#include "core/error.hpp"
#include "sweep_programs.hpp"

namespace tridex::compute {
namespace {

using test::box_model;
using test::compare;

constexpr int kCells = 48;
const Lattice kLattice = box_model(kCells, 0.0, 0.0).lattice;

Aabb grid_box(const Vec3& lo, const Vec3& hi) { return Aabb{kLattice.to_world(lo), kLattice.to_world(hi)}; }

// `model` with the closed mesh `mesh` (world m) added as material: scan-converted on the same lattice, then each ray
// united ray by ray.
void add_mesh(TriDexel& model, const TriMesh& mesh) {
    TriDexel part = TriDexel::empty(model.lattice, std::size_t{1} << 30);
    scan_convert(mesh, part);
    for (int a = 0; a < 3; ++a)
        for (std::size_t r = 0; r < part.sets[a].rays.size(); ++r)
            for (const Interval& iv : part.sets[a].rays[r]) union_interval_changed(model.sets[a].rays[r], iv.enter, iv.exit, 0);
}

// A box (grid units) turned by `degrees` about the y axis around its centre, as a mesh in world m.
TriMesh turned_box(const Vec3& lo, const Vec3& hi, double degrees) {
    TriMesh m = box_mesh(grid_box(lo, hi));
    const Vec3 c = kLattice.to_world(0.5 * (lo + hi));
    const double a = degrees * std::numbers::pi / 180.0;
    for (Vec3& p : m.positions) {
        const Vec3 d = p - c;
        p = c + Vec3(std::cos(a) * d.x + std::sin(a) * d.z, d.y, -std::sin(a) * d.x + std::cos(a) * d.z);
    }
    return m;
}

std::size_t components(TriDexel model) {
    std::fill(model.tiles.dirty.begin(), model.tiles.dirty.end(), std::uint8_t{1});
    Contourer c(model);
    c.update(model);
    return mesh_components(c.mesh());
}

TriDexel removed(TriDexel model, const IslandSearch& s) {
    for (const RayImage& r : s.rays) model.sets[r.axis].rays[r.index] = r.intervals;
    return model;
}

const double kCell3 = 1e-9;  // one cell, m^3 (1 mm cells)

TEST(FindIslands, ADetachedSmallCubeIsASpeckAndItsRaysRemoveItToTheBit) {
    const TriDexel body = box_model(kCells, 6.5, 30.5);
    TriDexel m = body;
    add_mesh(m, box_mesh(grid_box(Vec3(35.3), Vec3(38.6))));
    ASSERT_EQ(components(m), 2u);
    IslandOptions o;
    o.max_volume_m3 = speck_volume_m3(3e-3);  // a tool of 3 cells: 113 cells^3
    // The whole lattice: both are closed pieces, only the cube is a speck.
    const IslandSearch all = find_islands(m, kLattice.bounds(), o);
    EXPECT_EQ(all.pieces, 2u);
    ASSERT_EQ(all.closed.size(), 2u);
    ASSERT_EQ(all.specks.size(), 1u);
    // The volume is the rays' midpoint rule (3 x 3 rays of 3.3 cells per set for the cube): within a cell's layer.
    EXPECT_NEAR(all.specks[0].volume_m3, 3.3 * 3.3 * 3.3 * kCell3, 0.2 * 3.3 * 3.3 * 3.3 * kCell3);
    EXPECT_NEAR(all.closed[0].volume_m3, 24.0 * 24.0 * 24.0 * kCell3, 0.05 * 24.0 * 24.0 * 24.0 * kCell3);
    EXPECT_EQ(all.specks[0].nodes, 27u);
    EXPECT_EQ(all.speck_volume_m3, all.specks[0].volume_m3);
    EXPECT_TRUE(all.speck_box_m.contains(kLattice.to_world(Vec3(37.0))));
    EXPECT_EQ(compare(removed(m, all), body).rays, 0u) << "removing the speck gives the body alone, bit for bit";
    // A box around the cube that cuts through the body: the body touches its sides, the cube does not.
    const IslandSearch local = find_islands(m, grid_box(Vec3(25.0), Vec3(44.0)), o);
    EXPECT_EQ(local.pieces, 2u);
    ASSERT_EQ(local.closed.size(), 1u);
    ASSERT_EQ(local.specks.size(), 1u);
    EXPECT_EQ(compare(removed(m, local), body).rays, 0u);
    EXPECT_EQ(components(removed(m, local)), 1u);
    // A box that cuts through the cube: it may go on outside, so it is not a speck.
    const IslandSearch cut = find_islands(m, grid_box(Vec3(25.0), Vec3(37.0)), o);
    EXPECT_TRUE(cut.closed.empty());
    EXPECT_TRUE(cut.rays.empty());
}

TEST(FindIslands, AChunkLargerThanTheThresholdIsKept) {
    TriDexel m = box_model(kCells, 6.5, 24.5);
    add_mesh(m, box_mesh(grid_box(Vec3(30.5), Vec3(40.5))));  // 10 cells on a side: 1000 cells^3
    IslandOptions o;
    o.max_volume_m3 = speck_volume_m3(5e-3);  // 524 cells^3
    const IslandSearch s = find_islands(m, kLattice.bounds(), o);
    EXPECT_EQ(s.closed.size(), 2u);
    EXPECT_TRUE(s.specks.empty());
    EXPECT_TRUE(s.rays.empty());
    EXPECT_EQ(s.speck_volume_m3, 0.0);
}

TEST(FindIslands, AThinWallAndASlantedSheetTheLatticeResolvesStayWithTheBody) {
    TriDexel m = box_model(kCells, 6.5, 24.5);
    add_mesh(m, box_mesh(grid_box(Vec3(10.5, 10.5, 24.0), Vec3(11.7, 20.5, 34.5))));  // a wall 1.2 cells thick on top
    add_mesh(m, turned_box(Vec3(14.0, 8.5, 20.0), Vec3(15.6, 22.5, 40.0), 40.0));      // a sheet 1.6 cells thick, at 40 deg
    ASSERT_EQ(components(m), 1u);
    IslandOptions o;
    o.max_volume_m3 = speck_volume_m3(6.5e-3);  // 1150 cells^3: larger than wall and sheet, smaller than the block
    const IslandSearch all = find_islands(m, kLattice.bounds(), o);
    EXPECT_EQ(all.pieces, 1u);
    EXPECT_EQ(all.closed.size(), 1u);  // the body with wall and sheet, larger than the threshold
    EXPECT_TRUE(all.specks.empty());
    // Around the wall and the sheet, cutting through the body: nothing closed.
    const IslandSearch local = find_islands(m, grid_box(Vec3(8.0, 8.0, 22.0), Vec3(30.0, 30.0, 42.0)), o);
    EXPECT_EQ(local.pieces, 1u);
    EXPECT_TRUE(local.closed.empty());
}

TEST(FindIslands, ASheetThinnerThanTheLatticeResolvesFallsApartAsInTheMesh) {
    // A sheet 0.5 cell thick at 40 degrees, detached from the body: its lattice nodes are not neighbours, so the
    // contour draws it as many small blobs; the search finds one closed piece per blob.
    TriDexel m = box_model(kCells, 6.5, 20.5);
    add_mesh(m, turned_box(Vec3(24.0, 10.5, 24.0), Vec3(24.5, 38.5, 42.0), 40.0));
    const std::size_t mesh_parts = components(m);
    ASSERT_GT(mesh_parts, 3u);
    IslandOptions o;
    o.max_volume_m3 = speck_volume_m3(3e-3);
    const IslandSearch s = find_islands(m, kLattice.bounds(), o);
    EXPECT_EQ(s.pieces, mesh_parts);
    EXPECT_EQ(s.specks.size(), mesh_parts - 1);
    EXPECT_EQ(components(removed(m, s)), 1u);
}

TEST(FindIslands, OnRandomCutsThePiecesAreTheMeshsComponentsAndRemovingTheSpecksLeavesOne) {
    for (std::uint32_t seed = 1; seed <= 6; ++seed) {
        TriDexel m = box_model(kCells, 6.5, 41.5);
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> u(4.0, 44.0), r(1.5, 5.0);
        for (int i = 0; i < 60; ++i) {
            // Subtract only, each cut from outside the box: the air stays connected (no closed cavity, which would be
            // a mesh component of its own), so every extra component of the mesh is a piece.
            Sweep s;
            s.op = ToolOp::kSubtract;
            s.tool = SweepTool{ToolKind::kBall, r(rng) * 1e-3, 0.0};
            Vec3 a(u(rng), u(rng), u(rng));
            a[static_cast<int>(rng() % 3)] = rng() % 2 ? 2.5 : 45.5;
            s.path_m = Segment{kLattice.to_world(a), kLattice.to_world(Vec3(u(rng), u(rng), u(rng)))};
            apply_sweep(m, s);
        }
        IslandOptions o;
        o.max_volume_m3 = 0.5 * dexel_volume_m3(m);  // everything but the largest piece
        const IslandSearch s = find_islands(m, kLattice.bounds(), o);
        EXPECT_EQ(s.pieces, components(m)) << "seed " << seed;
        EXPECT_EQ(s.specks.size() + 1, s.pieces) << "seed " << seed;
        const TriDexel clean = removed(m, s);
        EXPECT_EQ(components(clean), 1u) << "seed " << seed;
        EXPECT_EQ(find_islands(clean, kLattice.bounds(), o).specks.size(), 0u) << "seed " << seed;
    }
}

TEST(FindIslands, RefusesBadInputAndFindsNothingOutsideTheLattice) {
    const TriDexel m = box_model(kCells, 6.5, 30.5);
    IslandOptions o;
    o.max_volume_m3 = -1.0;
    EXPECT_THROW(find_islands(m, kLattice.bounds(), o), Error);
    o.max_volume_m3 = std::nan("");
    EXPECT_THROW(find_islands(m, kLattice.bounds(), o), Error);
    o.max_volume_m3 = 1.0;
    EXPECT_THROW(find_islands(m, Aabb{Vec3(0.0), Vec3(std::numeric_limits<double>::infinity())}, o), Error);
    EXPECT_EQ(find_islands(m, Aabb{}, o).pieces, 0u);
    EXPECT_EQ(find_islands(m, kLattice.bounds().inflated(-1.0), o).pieces, 0u);  // inside out: empty
    const Aabb beside{kLattice.bounds().hi + Vec3(1.0), kLattice.bounds().hi + Vec3(2.0)};
    EXPECT_EQ(find_islands(m, beside, o).pieces, 0u);
    EXPECT_EQ(speck_volume_m3(-1.0), 0.0);
    EXPECT_EQ(speck_volume_m3(std::nan("")), 0.0);
    EXPECT_NEAR(speck_volume_m3(0.006), 4.0 / 3.0 * std::numbers::pi * 2.16e-7, 1e-15);
}

}  // namespace
}  // namespace tridex::compute
