// Tests of the lattice choice, the model's memory check and dirty-tile marking.
#include <gtest/gtest.h>

#include <string>

#include "compute/tridexel.hpp"
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

TEST(TriDexel, MarkDirtyCoversTheBoxPlusOneCellAndNothingFar) {
    const Lattice l = Lattice::around(Aabb{Vec3(0.0), Vec3(1.0)}, 68, 2);  // 68 cells: tiles 0..4 per axis
    TriDexel m = TriDexel::empty(l, std::size_t(1) << 30);
    ASSERT_EQ(m.tiles.tiles[0], 5);
    // A box inside cells [16.5, 17.5] on every axis: with one cell around it, cells 15..18 -> tiles 0 and 1.
    m.mark_dirty(Aabb{l.to_world(Vec3(16.5)), l.to_world(Vec3(17.5))});
    for (int z = 0; z < 5; ++z)
        for (int y = 0; y < 5; ++y)
            for (int x = 0; x < 5; ++x)
                EXPECT_EQ(m.tiles.dirty[m.tiles.index(x, y, z)], (x <= 1 && y <= 1 && z <= 1) ? 1 : 0) << x << y << z;
    m.clear_dirty();
    m.mark_dirty(Aabb{l.to_world(Vec3(-50.0)), l.to_world(Vec3(-40.0))});  // outside the lattice
    for (auto d : m.tiles.dirty) EXPECT_EQ(d, 0);
}

}  // namespace
}  // namespace tridex::compute
