// Tests of TileSurfaceCache's pass over the groups' cover and waiting errors once start-up's tiles are all in: during
// strokes drawn coarse (defer_tiles) it looks only at the groups over the stroke's hidden tiles, those it left
// uncovered and those whose level waits to be measured, and leaves every group as a pass over all of them does; and
// in a coarse-first start-up the passes of a stroke's steps leave the levels' errors to measure for after it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/deferred_contour.hpp"
#include "compute/contour/held_tiles.hpp"
#include "compute/tools/boolean.hpp"
#include "test_coarse_first_session.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;

// A session with every tile contoured at start-up and the coarse group levels, whose strokes are drawn coarse: each
// step's tiles are deferred and hidden, and contoured between strokes, as the sculpt thread does.
struct Session {
    TriDexel model = off_centre_sphere();
    Contourer contourer{model};
    DeferredContour deferral{model.tiles.tiles};
    TileSurfaceCache cache;

    explicit Session(bool every) {
        contourer.update(model);
        use_coarse_lod(cache, model);
        cache.pass_every_group(every);
        refresh();
        for (int i = 0; i < 400; ++i) cache.collect_lods();
    }
    void refresh() { refresh_held_tiles(cache, contourer, nullptr, &deferral); }
    // A step's tiles deferred, then the background's collect (its pass runs before the refresh regroups them), then
    // the refresh, as the sculpt thread does.
    void defer_step(int k, int side) {
        groove_cut(model, k, side);
        cache.defer_tiles(deferral.defer(model));
        cache.collect_lods();
    }
    void between_strokes(std::size_t tiles) {
        deferral.contour_oldest(model, contourer, tiles);
        refresh();
        for (int i = 0; i < 8; ++i) cache.collect_lods();
    }
};

// The same groups, cover, levels and level errors in both caches.
void expect_same_groups(const TileSurfaceCache& a, const TileSurfaceCache& b) {
    ASSERT_EQ(a.groups().size(), b.groups().size());
    for (std::size_t i = 0; i < a.groups().size(); ++i) {
        const TileGroupSurface& x = a.groups()[i];
        const TileGroupSurface& y = b.groups()[i];
        ASSERT_EQ(x.id, y.id);
        EXPECT_EQ(x.children_cover, y.children_cover) << "group " << x.id;
        ASSERT_EQ(x.lods.size(), y.lods.size()) << "group " << x.id;
        if (!x.lods.empty()) {
            EXPECT_EQ(x.lods[0].error_m, y.lods[0].error_m) << "group " << x.id;
            EXPECT_EQ(x.lods[0].mesh.positions, y.lods[0].mesh.positions) << "group " << x.id;
        }
    }
}

std::size_t uncovered(const TileSurfaceCache& c) {
    std::size_t n = 0;
    for (const TileGroupSurface& g : c.groups()) n += g.children_cover ? 0 : 1;
    return n;
}

// Two strokes on two sides, the first's tiles then contoured all at once, the second's a batch at a time: after every
// step the cache whose passes look at a few groups holds what the one whose passes look at all of them holds.
TEST(StrokeCover, APassOverTheStrokesGroupsLeavesEveryGroupAsAWholePassDoes) {
    Session few(false), all(true);
    expect_same_groups(few.cache, all.cache);
    std::size_t most_uncovered = 0, fewest_visits = few.cache.groups().size(), passes = 0;
    const auto step = [&](const std::string& what, bool refreshed = true) {
        SCOPED_TRACE(what);
        expect_same_groups(few.cache, all.cache);
        if (!refreshed) return;  // the collect may not have run a pass
        EXPECT_EQ(all.cache.last_group_pass_visits(), all.cache.groups().size());
        most_uncovered = std::max(most_uncovered, uncovered(few.cache));
        if (few.cache.expected_tiles() > 0) {
            ++passes;
            fewest_visits = std::min(fewest_visits, few.cache.last_group_pass_visits());
        }
    };
    for (int side = 0; side < 2; ++side) {
        for (int k = 0; k < 4; ++k) {
            few.defer_step(k, side);
            all.defer_step(k, side);
            step("stroke " + std::to_string(side) + " step " + std::to_string(k) + ", before its refresh", false);
            few.refresh();
            all.refresh();
            step("stroke " + std::to_string(side) + " step " + std::to_string(k));
        }
        // After the first stroke every tile at once, before its groups' levels are rebuilt (they wait to settle):
        // groups left uncovered then have all their tiles in and no level waiting to be measured.
        const std::size_t tiles = side == 0 ? 100000 : 6;
        for (int batch = 0; batch < 3; ++batch) {
            few.between_strokes(tiles);
            all.between_strokes(tiles);
            step("batch " + std::to_string(batch) + " after stroke " + std::to_string(side));
        }
    }
    few.between_strokes(100000);
    all.between_strokes(100000);
    step("every tile contoured");
    EXPECT_EQ(few.cache.expected_tiles(), 0u);
    EXPECT_EQ(uncovered(few.cache), 0u);
    std::printf(
        "[stroke cover] %zu groups; passes during strokes looked at %zu of them at least; up to %zu uncovered\n",
        few.cache.groups().size(), fewest_visits, most_uncovered);
    EXPECT_GT(passes, 8u);
    EXPECT_GT(most_uncovered, 0u) << "no stroke left a group uncovered: the comparison would not see a wrong cover";
    EXPECT_GT(fewest_visits, 0u);
    EXPECT_LT(fewest_visits, few.cache.groups().size() / 4) << "the passes during strokes looked at most groups";
}

// In a coarse-first start-up, with the stroke's rebuilt levels waiting to be estimated and refined groups' levels
// to be measured: the passes of a stroke's steps (its refresh, the collect with the stroke open) set the cover and
// rate no level's error, so that the step's samples do not wait for that work; the first collect after the stroke
// takes it up again.
TEST(StrokeCover, AStrokesPassesLeaveTheLevelsErrorsForAfterIt) {
    CoarseFirst s;
    while (s.cache.build_coarse_depth()) {}
    settle(s.cache);  // every level in, and every estimate made
    for (int i = 0; i < 30; ++i) ASSERT_GT(s.refiner->refine_next(s.model, s.contourer), 0u);
    s.refresh();
    const std::size_t before = s.cache.startup_errors_rated();
    for (int k = 0; k < 3; ++k) {  // a stroke's steps across the sphere's +z side, away from the refined regions
        SCOPED_TRACE("step " + std::to_string(k));
        groove_cut(s.model, k);
        const std::vector<std::uint32_t> d = s.model.tiles.dirty_tiles();
        ASSERT_FALSE(d.empty());
        s.model.clear_dirty();
        s.cache.defer_tiles(std::vector<std::uint64_t>(d.begin(), d.end()));
        s.refresh();
        EXPECT_EQ(s.cache.startup_errors_rated(), before) << "the step's refresh rated a level's error";
        for (int i = 0; i < 4; ++i) s.cache.collect_lods(true);
        EXPECT_EQ(s.cache.startup_errors_rated(), before) << "a collect with the stroke open rated a level's error";
    }
    s.cache.collect_lods();
    const std::size_t after = s.cache.startup_errors_rated() - before;
    std::printf("[stroke cover] level errors rated by the first collect after the stroke: %zu\n", after);
    EXPECT_GT(after, 0u) << "no level's error waited: the stroke's passes had nothing to leave";
}

}  // namespace
}  // namespace tridex::compute
