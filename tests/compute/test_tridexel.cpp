// Tests of the lattice choice, the model's memory check and dirty-tile marking.
#include <gtest/gtest.h>

#include <array>
#include <string>

#include "compute/model/tridexel.hpp"
#include "core/error.hpp"

namespace tridex::compute {
namespace {

TEST(Lattice, LongestSideGetsTheResolutionWithMarginAndShortSidesAreCentred) {
    const Aabb box{Vec3(0.0), Vec3(0.3, 0.15, 0.1)};
    const Lattice l = Lattice::around(box, 64, 2);
    EXPECT_EQ(l.cells[0], 64);
    EXPECT_DOUBLE_EQ(l.cell_m, 0.3 / 60.0);
    for (int a = 0; a < 3; ++a) {
        // The box lies inside the lattice with at least the margin on both ends, centred.
        const double lo_gap = box.lo[a] - l.origin_m[a];
        const double hi_gap = l.bounds().hi[a] - box.hi[a];
        EXPECT_GE(lo_gap, 2.0 * l.cell_m - 1e-12) << a;
        EXPECT_NEAR(lo_gap, hi_gap, 1e-12) << a;
    }
}

TEST(Lattice, RefusesImpossibleInput) {
    EXPECT_THROW(Lattice::around(Aabb{Vec3(0.0), Vec3(1.0)}, 5, 2), Error);  // no room inside the margin
    EXPECT_THROW(Lattice::around(Aabb{}, 64, 2), Error);                      // empty box
    EXPECT_THROW(Lattice::around(Aabb{Vec3(0.0), Vec3(0.0)}, 64, 2), Error);  // a point
}

TEST(TriDexel, RefusesAResolutionThatDoesNotFitWithTheNumbersInTheMessage) {
    const Lattice l = Lattice::around(Aabb{Vec3(0.0), Vec3(1.0)}, 1024, 2);
    try {
        TriDexel::empty(l, std::size_t(64) << 20);  // 64 MiB for 3 x 1025^2 rays
        FAIL() << "no error";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("1024x1024x1024"), std::string::npos) << msg;
        EXPECT_NE(msg.find("64 MiB"), std::string::npos) << msg;
        EXPECT_NE(msg.find("--resolution"), std::string::npos) << msg;
    }
}

TEST(TriDexel, EmptyModelHasOneRayPerLatticeNodeAndCleanTiles) {
    const Lattice l = Lattice::around(Aabb{Vec3(0.0), Vec3(1.0, 0.5, 0.25)}, 40, 2);
    const TriDexel m = TriDexel::empty(l, std::size_t(1) << 30);
    for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(m.sets[a].nu, l.nodes((a + 1) % 3));
        EXPECT_EQ(m.sets[a].nv, l.nodes((a + 2) % 3));
        EXPECT_EQ(m.sets[a].rays.size(), static_cast<std::size_t>(m.sets[a].nu) * m.sets[a].nv);
        EXPECT_EQ(m.tiles.tiles[a], (l.cells[a] + TileGrid::kTileCells - 1) / TileGrid::kTileCells);
    }
    EXPECT_EQ(m.interval_count(), 0u);
    for (auto d : m.tiles.dirty) EXPECT_EQ(d, 0);
}

/// Marks the box [lo, hi] (grid units, per axis) on a clean model and expects exactly the tiles
/// tlo[a] .. thi[a] on every axis a dirty (none at all when tlo[0] > thi[0]).
void expect_marked_tiles(TriDexel& m, const Vec3& lo, const Vec3& hi, std::array<int, 3> tlo, std::array<int, 3> thi) {
    m.clear_dirty();
    m.mark_dirty(Aabb{m.lattice.to_world(lo), m.lattice.to_world(hi)});
    const auto& n = m.tiles.tiles;
    for (int z = 0; z < n[2]; ++z)
        for (int y = 0; y < n[1]; ++y)
            for (int x = 0; x < n[0]; ++x) {
                const bool in = x >= tlo[0] && x <= thi[0] && y >= tlo[1] && y <= thi[1] && z >= tlo[2] && z <= thi[2];
                EXPECT_EQ(m.tiles.dirty[m.tiles.index(x, y, z)] != 0, in) << "tile " << x << "," << y << "," << z;
            }
}

TEST(TriDexel, MarkDirtyCoversExactlyFourCellsAroundTheBox) {
    // Cells floor(lo) - 4 .. floor(hi) + 4 per axis (clamped to the lattice) are covered; tiles are 16
    // cells. Every case below gives a different tile set for a margin of 3 cells or of 5 (noted per axis),
    // so both a too small and a too large reach fail.
    const Lattice l = Lattice::around(Aabb{Vec3(0.0), Vec3(1.0)}, 68, 2);  // 68 cells: tiles 0..4 per axis
    TriDexel m = TriDexel::empty(l, std::size_t(1) << 30);
    ASSERT_EQ(m.tiles.tiles[0], 5);
    ASSERT_EQ(m.lattice.cells[0], 68);
    // x [19.5, 20.5]: cells 15..24 -> tiles 0..1 (margin 3: from cell 16 -> tile 1 only);
    // y [11.5, 11.9]: cells 7..15 -> tile 0 (margin 5: up to cell 16 -> tiles 0..1);
    // z [27.5, 27.9]: cells 23..31 -> tile 1 (margin 5: up to cell 32 -> tiles 1..2).
    expect_marked_tiles(m, Vec3(19.5, 11.5, 27.5), Vec3(20.5, 11.9, 27.9), {0, 0, 1}, {1, 0, 1});
    // x [35.5, 36.5]: cells 31..40 -> tiles 1..2 (margin 3: from cell 32 -> tile 2 only);
    // y [43.5, 43.9]: cells 39..47 -> tile 2 (margin 5: up to cell 48 -> tiles 2..3);
    // z [59.2, 59.4]: cells 55..63 -> tile 3 (margin 5: up to cell 64 -> tiles 3..4).
    expect_marked_tiles(m, Vec3(35.5, 43.5, 59.2), Vec3(36.5, 43.9, 59.4), {1, 2, 3}, {2, 2, 3});
    // Clamping at the lattice ends: x [-2.5, -1.5] -> cells -7..2 -> tile 0; y [66.5, 69.5] -> cells
    // 62..73, clamped to 62..67 -> tiles 3..4; z [0.5, 0.7] -> cells -4..4 -> tile 0.
    expect_marked_tiles(m, Vec3(-2.5, 66.5, 0.5), Vec3(-1.5, 69.5, 0.7), {0, 3, 0}, {0, 4, 0});
    // Just within reach outside the lattice: x [-10, -4.5] reaches cell floor(-4.5) + 4 = -1, no cell
    // (margin 5: cell 0 -> tile 0); x [70.5, 80] reaches down to cell 66 -> tile 4; x [72.5, 80]
    // reaches down to cell 68, no cell (margin 5: cell 67 -> tile 4).
    expect_marked_tiles(m, Vec3(-10.0, 20.5, 20.5), Vec3(-4.5, 21.5, 21.5), {1, 0, 0}, {0, 0, 0});
    expect_marked_tiles(m, Vec3(70.5, 20.5, 20.5), Vec3(80.0, 21.5, 21.5), {4, 1, 1}, {4, 1, 1});
    expect_marked_tiles(m, Vec3(72.5, 20.5, 20.5), Vec3(80.0, 21.5, 21.5), {1, 0, 0}, {0, 0, 0});
    // Far outside, and an empty box: nothing.
    expect_marked_tiles(m, Vec3(-50.0), Vec3(-40.0), {1, 0, 0}, {0, 0, 0});
    m.clear_dirty();
    m.mark_dirty(Aabb{});
    for (auto d : m.tiles.dirty) EXPECT_EQ(d, 0);
}

TEST(TriDexel, MarkDirtyAddsToFlagsAlreadySet) {
    const Lattice l = Lattice::around(Aabb{Vec3(0.0), Vec3(1.0)}, 68, 2);
    TriDexel m = TriDexel::empty(l, std::size_t(1) << 30);
    m.mark_dirty(Aabb{l.to_world(Vec3(8.5)), l.to_world(Vec3(9.5))});    // cells 4..13: tile (0, 0, 0)
    m.mark_dirty(Aabb{l.to_world(Vec3(56.5)), l.to_world(Vec3(57.5))});  // cells 52..61: tile (3, 3, 3)
    std::size_t n = 0;
    for (auto d : m.tiles.dirty) n += d != 0 ? 1 : 0;
    EXPECT_EQ(n, 2u);
    EXPECT_EQ(m.tiles.dirty[m.tiles.index(0, 0, 0)], TileGrid::kPartial);
    EXPECT_EQ(m.tiles.dirty[m.tiles.index(3, 3, 3)], TileGrid::kPartial);
}

void expect_cells(const TriDexel& m, std::array<int, 3> tile, std::array<int, 3> lo, std::array<int, 3> hi) {
    const CellBox* box = m.tiles.partial_cells(m.tiles.index(tile[0], tile[1], tile[2]));
    ASSERT_NE(box, nullptr) << "tile " << tile[0] << "," << tile[1] << "," << tile[2] << " is not partial";
    EXPECT_EQ(box->lo, lo) << "tile " << tile[0] << "," << tile[1] << "," << tile[2];
    EXPECT_EQ(box->hi, hi) << "tile " << tile[0] << "," << tile[1] << "," << tile[2];
}

TEST(TriDexel, MarkDirtyKeepsEachTilesChangedCells) {
    const Lattice l = Lattice::around(Aabb{Vec3(0.0), Vec3(1.0)}, 68, 2);  // tiles of cells 0..15, 16..31, ...
    TriDexel m = TriDexel::empty(l, std::size_t(1) << 30);
    const auto mark = [&](Vec3 lo, Vec3 hi) { m.mark_dirty(Aabb{l.to_world(lo), l.to_world(hi)}); };
    // Cells x 15..24, y 7..15, z 23..31: tile x 0 gets cell 15 only, tile x 1 cells 16..24.
    mark(Vec3(19.5, 11.5, 27.5), Vec3(20.5, 11.9, 27.9));
    expect_cells(m, {0, 0, 1}, {15, 7, 23}, {15, 15, 31});
    expect_cells(m, {1, 0, 1}, {16, 7, 23}, {24, 15, 31});
    // A second box (cells x 22..30, y 2..10, z 20..28) grows each tile's box to the union of both.
    mark(Vec3(26.5, 6.5, 24.5), Vec3(26.7, 6.7, 24.7));
    expect_cells(m, {1, 0, 1}, {16, 2, 20}, {30, 15, 31});
    expect_cells(m, {0, 0, 1}, {15, 7, 23}, {15, 15, 31});  // untouched by the second box
    // A box covering a tile's every cell makes it whole; so does writing kWhole, which no later box narrows.
    mark(Vec3(35.0, 35.0, 35.0), Vec3(44.0, 44.0, 44.0));  // cells 31..48: tile 2 whole
    EXPECT_EQ(m.tiles.dirty[m.tiles.index(2, 2, 2)], TileGrid::kWhole);
    EXPECT_EQ(m.tiles.partial_cells(m.tiles.index(2, 2, 2)), nullptr);
    m.tiles.dirty[m.tiles.index(0, 0, 1)] = TileGrid::kWhole;
    mark(Vec3(10.5, 11.5, 27.5), Vec3(10.7, 11.9, 27.9));
    EXPECT_EQ(m.tiles.dirty[m.tiles.index(0, 0, 1)], TileGrid::kWhole);
    EXPECT_EQ(m.tiles.partial_cells(m.tiles.index(0, 0, 1)), nullptr);
    // Clearing forgets the boxes: the next box starts a new one.
    m.clear_dirty();
    mark(Vec3(26.5, 6.5, 24.5), Vec3(26.7, 6.7, 24.7));
    expect_cells(m, {1, 0, 1}, {22, 2, 20}, {30, 10, 28});
}

}  // namespace
}  // namespace tridex::compute
