// Tests of renderer/scene/tile_lod: the projected size of a metre in a tile's box for an off-axis eye, and the
// level chosen from it (a far eye picks a coarser level than a near eye; never a level whose error exceeds the
// pixel budget; the full mesh when the box reaches the eye's plane).
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "renderer/scene/tile_group_lod.hpp"
#include "renderer/scene/tile_lod.hpp"

namespace tridex::renderer {
namespace {

Aabb box_at(const Vec3& c, double half) { return Aabb{c - Vec3(half), c + Vec3(half)}; }

TEST(TileLod, PixelsPerMetreMatchesTheScreenProjection) {
    const Screen wall = Screen::powerwall();  // 3.048 m x 2.286 m in z = 0
    const LodEye eye = lod_eye(wall, Vec3(0.0, 0.0, 1.0), 1280, 720);
    EXPECT_NEAR(eye.screen_distance_m, 1.0, 1e-12);
    EXPECT_NEAR(eye.pixels_per_screen_m, 1280 / 3.048, 1e-9);
    // A point half way to the screen, straight ahead: lengths there appear twice as long on the screen.
    EXPECT_NEAR(pixels_per_metre(eye, box_at(Vec3(0.0, 0.0, 0.5), 0.0)), 2.0 * 1280 / 3.048, 1e-6);
    // Off to the side by as much as it is deep: the depth direction projects too (sqrt(2)).
    EXPECT_NEAR(pixels_per_metre(eye, box_at(Vec3(0.5, 0.0, 0.5), 0.0)), 2.0 * std::sqrt(2.0) * 1280 / 3.048, 1e-6);
    // The nearest corner of a box decides.
    EXPECT_NEAR(pixels_per_metre(eye, Aabb{Vec3(0.0, 0.0, 0.2), Vec3(0.0, 0.0, 0.5)}), 2.0 * 1280 / 3.048, 1e-6);
    // Reaching the eye's plane: unbounded; empty: zero; not finite: refused.
    EXPECT_TRUE(std::isinf(pixels_per_metre(eye, Aabb{Vec3(0.0, 0.0, 0.5), Vec3(0.0, 0.0, 1.5)})));
    EXPECT_EQ(pixels_per_metre(eye, Aabb{}), 0.0);
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_THROW(pixels_per_metre(eye, Aabb{Vec3(0.0), Vec3(inf)}), Error);
    EXPECT_THROW(lod_eye(wall, Vec3(0.0, 0.0, 1.0), 0, 720), Error);
    EXPECT_THROW(lod_eye(wall, Vec3(0.0, 0.0, -1.0), 1280, 720), Error);
}

TEST(TileLod, FarEyePicksACoarserLevelThanNearEye) {
    TriMesh tri;
    tri.positions = {Vec3(0.0), Vec3(1.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0)};
    tri.triangles = {{0, 1, 2}};
    // Errors 0.5, 1, 2, 4 mm.
    std::vector<TileMeshLevel> levels;
    for (double e : {0.5e-3, 1e-3, 2e-3, 4e-3}) levels.push_back(TileMeshLevel{&tri, nullptr, nullptr, e});
    const Screen wall = Screen::powerwall();
    const Aabb tile = box_at(Vec3(0.0, 0.0, 0.3), 0.01);
    std::size_t previous = 0;
    for (double z : {0.4, 0.65, 1.5, 3.0, 8.0}) {
        const LodEye eye = lod_eye(wall, Vec3(0.0, 0.1, z), 1280, 720);
        const double ppm = pixels_per_metre(eye, tile);
        const std::size_t k = choose_level(levels, ppm, 1.0);
        EXPECT_GE(k, previous) << "eye at z = " << z;  // never finer when farther
        if (k > 0) {
            EXPECT_LE(levels[k - 1].error_m * ppm, 1.0);
        }
        if (k < levels.size()) {
            EXPECT_GT(levels[k].error_m * ppm, 1.0);  // the next coarser one would not do
        }
        previous = k;
    }
    const LodEye near = lod_eye(wall, Vec3(0.0, 0.1, 0.4), 1280, 720), far = lod_eye(wall, Vec3(0.0, 0.1, 3.0), 1280, 720);
    const std::size_t k_near = choose_level(levels, pixels_per_metre(near, tile), 1.0);
    const std::size_t k_far = choose_level(levels, pixels_per_metre(far, tile), 1.0);
    EXPECT_LT(k_near, k_far);
    // A larger pixel budget allows coarser levels; a level without a mesh is never chosen.
    EXPECT_GE(choose_level(levels, pixels_per_metre(near, tile), 4.0), k_near);
    EXPECT_EQ(choose_level(levels, 1.0, 1e9), levels.size());
    levels.back().mesh = nullptr;
    EXPECT_EQ(choose_level(levels, 1.0, 1e9), levels.size() - 1);
    EXPECT_EQ(choose_level(levels, std::numeric_limits<double>::infinity(), 1.0), 0u);
    EXPECT_EQ(choose_level({}, 1.0, 1.0), 0u);
}

// Groups with the given levels and parent indices, in that order.
std::vector<TileGroup> group_tree(std::initializer_list<std::pair<std::span<const TileMeshLevel>, std::size_t>> spec) {
    std::vector<TileGroup> groups;
    for (const auto& [levels, parent] : spec) {
        groups.emplace_back();
        groups.back().levels = levels;
        groups.back().parent = parent;
    }
    return groups;
}

// A tree of groups: root 0 over groups 1 and 2; group 3 under 1. Errors grow with size.
TEST(TileGroupLod, GroupsObeyTheBoundAndCoverTheirChildrenOnce) {
    TriMesh tri;
    tri.positions = {Vec3(0.0), Vec3(1.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0)};
    tri.triangles = {{0, 1, 2}};
    const auto levels = [&](std::initializer_list<double> errors) {
        std::vector<TileMeshLevel> l;
        for (double e : errors) l.push_back(TileMeshLevel{&tri, nullptr, nullptr, e});
        return l;
    };
    const std::vector<TileMeshLevel> root = levels({4e-3, 8e-3}), a = levels({2e-3, 4e-3}), b = levels({1e-3}),
                                     c = levels({0.5e-3, 1e-3});
    std::vector<TileGroup> groups = group_tree({{root, TileGroup::kNone}, {a, 0}, {b, 0}, {c, 1}});
    std::vector<std::uint8_t> covered;
    // Far: the root's coarsest level alone; everything under it is covered.
    std::vector<std::size_t> k = choose_group_levels(groups, std::vector<double>(4, 100.0), 1.0, covered);
    EXPECT_EQ(k, (std::vector<std::size_t>{2, 0, 0, 0}));
    EXPECT_EQ(covered, (std::vector<std::uint8_t>{0, 1, 1, 1}));
    // Nearer: the root is too coarse (4 mm * 400 px/m = 1.6 px); groups 1 (2 mm: 0.8 px) and 2 are drawn.
    k = choose_group_levels(groups, std::vector<double>(4, 400.0), 1.0, covered);
    EXPECT_EQ(k, (std::vector<std::size_t>{0, 1, 1, 0}));
    EXPECT_EQ(covered, (std::vector<std::uint8_t>{0, 0, 0, 1}));
    // Nearer still: only the smallest group fits; the others leave their tiles to themselves.
    k = choose_group_levels(groups, std::vector<double>(4, 1500.0), 1.0, covered);
    EXPECT_EQ(k, (std::vector<std::size_t>{0, 0, 0, 1}));
    EXPECT_EQ(covered, (std::vector<std::uint8_t>{0, 0, 0, 0}));
    // Whatever the scales, every chosen level is within the bound and no drawn group lies under another.
    for (double s : {10.0, 150.0, 260.0, 900.0, 3000.0}) {
        const std::vector<double> px{s, 1.3 * s, 0.7 * s, 2.0 * s};
        k = choose_group_levels(groups, px, 1.0, covered);
        for (std::size_t g = 0; g < groups.size(); ++g) {
            if (k[g] > 0) {
                EXPECT_LE(groups[g].levels[k[g] - 1].error_m * px[g], 1.0);
                EXPECT_FALSE(covered[g]);
                for (std::size_t p = groups[g].parent; p != TileGroup::kNone; p = groups[p].parent) EXPECT_EQ(k[p], 0u);
            }
            const std::size_t p = groups[g].parent;
            EXPECT_EQ(covered[g] != 0, p != TileGroup::kNone && (covered[p] || k[p] > 0)) << "scale " << s;
        }
    }
    // A group without levels is never drawn; bad input is refused.
    groups[0].levels = {};
    k = choose_group_levels(groups, std::vector<double>(4, 100.0), 1.0, covered);
    EXPECT_EQ(k[0], 0u);
    EXPECT_EQ(k[1], 2u);
    EXPECT_THROW(choose_group_levels(groups, std::vector<double>(3, 1.0), 1.0, covered), Error);
    groups[0].parent = 3;  // 0 -> 3 -> 1 -> 0
    EXPECT_THROW(choose_group_levels(groups, std::vector<double>(4, 1.0), 1.0, covered), Error);
    groups[0].parent = 9;
    EXPECT_THROW(choose_group_levels(groups, std::vector<double>(4, 1.0), 1.0, covered), Error);
}

// A coarse-first start-up: a group whose children cannot cover it yet is drawn whatever its error (its finest level
// when none is within the bound), unless an enclosing group is drawn; once they cover it, the bound decides again.
TEST(TileGroupLod, AGroupItsChildrenCannotCoverIsDrawnWhateverItsError) {
    TriMesh tri;
    tri.positions = {Vec3(0.0), Vec3(1.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0)};
    tri.triangles = {{0, 1, 2}};
    const std::vector<TileMeshLevel> root{TileMeshLevel{&tri, nullptr, nullptr, 8e-3}},
        child{TileMeshLevel{&tri, nullptr, nullptr, 2e-3}, TileMeshLevel{&tri, nullptr, nullptr, 4e-3}};
    std::vector<TileGroup> groups(3);
    groups[0].levels = root;
    groups[1].levels = child;
    groups[1].parent = 0;
    groups[2].levels = child;
    groups[2].parent = 0;
    std::vector<std::uint8_t> covered;
    const std::vector<double> near(3, 5000.0);  // every level strays by pixels
    EXPECT_EQ(choose_group_levels(groups, near, 1.0, covered), (std::vector<std::size_t>{0, 0, 0}));
    groups[1].children_cover = false;  // its tiles are not contoured yet: its finest level stands in
    EXPECT_EQ(choose_group_levels(groups, near, 1.0, covered), (std::vector<std::size_t>{0, 1, 0}));
    groups[0].children_cover = false;  // the root must be drawn: it covers both
    EXPECT_EQ(choose_group_levels(groups, near, 1.0, covered), (std::vector<std::size_t>{1, 0, 0}));
    EXPECT_EQ(covered, (std::vector<std::uint8_t>{0, 1, 1}));
    // Far away the bound picks the root anyway; without levels a group cannot be forced.
    EXPECT_EQ(choose_group_levels(groups, std::vector<double>(3, 100.0), 1.0, covered), (std::vector<std::size_t>{1, 0, 0}));
    groups[0].levels = {};
    EXPECT_EQ(choose_group_levels(groups, near, 1.0, covered), (std::vector<std::size_t>{0, 1, 0}));
}

// A group drawn only because nothing under it can draw its surface, over the bound: the eye wants its tiles.
TEST(TileGroupLod, AGroupDrawnOverTheBoundForItsChildrenWantsDetail) {
    TriMesh tri;
    tri.positions = {Vec3(0.0), Vec3(1.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0)};
    tri.triangles = {{0, 1, 2}};
    const std::vector<TileMeshLevel> levels{TileMeshLevel{&tri, nullptr, nullptr, 2e-3}};
    TileGroup g;
    g.levels = levels;
    EXPECT_TRUE(wants_detail(g, 1, 5000.0, 1.0, true));    // 10 px over a 1 px bound
    EXPECT_FALSE(wants_detail(g, 1, 400.0, 1.0, true));    // 0.8 px: within the bound, the level is what the eye wants
    EXPECT_TRUE(wants_detail(g, 1, 1500.0, 2.0, true));    // 3 px over a 2 px bound
    EXPECT_FALSE(wants_detail(g, 0, 5000.0, 1.0, true));   // not drawn
    EXPECT_FALSE(wants_detail(g, 2, 5000.0, 1.0, true));   // no such level
    EXPECT_FALSE(wants_detail(g, 1, 5000.0, 1.0, false));  // its children can be drawn instead: the bound decides
    // The bound alone (what a frame names in FrameStats::groups_at_level).
    EXPECT_FALSE(level_within_bound(g, 1, 5000.0, 1.0));  // 10 px over a 1 px bound
    EXPECT_TRUE(level_within_bound(g, 1, 400.0, 1.0));    // 0.8 px
    EXPECT_TRUE(level_within_bound(g, 1, 500.0, 1.0));    // 1 px: on the bound is within it
    EXPECT_FALSE(level_within_bound(g, 0, 400.0, 1.0));   // not drawn
    EXPECT_FALSE(level_within_bound(g, 2, 400.0, 1.0));   // no such level
}

// After a change, the finer groups' levels wait to be rebuilt while their tiles are all in. A group over the bound
// then stands in for them, drawn at its finest level, rather than let them draw its surface from their tiles at full
// resolution; once their levels are back, the bound decides again.
TEST(TileGroupLod, AGroupStandsInForChildrenWhoseLevelsWait) {
    TriMesh tri;
    tri.positions = {Vec3(0.0), Vec3(1.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0)};
    tri.triangles = {{0, 1, 2}};
    const std::vector<TileMeshLevel> root{TileMeshLevel{&tri, nullptr, nullptr, 8e-3}},
        child{TileMeshLevel{&tri, nullptr, nullptr, 2e-3}}, none{};
    // Root 0 over groups 1 and 2; group 3 under 2.
    std::vector<TileGroup> groups = group_tree({{root, TileGroup::kNone}, {child, 0}, {child, 0}, {child, 2}});
    std::vector<std::uint8_t> covered;
    const std::vector<double> mid(4, 400.0);  // the root strays by 3.2 px, the others by 0.8 px
    EXPECT_EQ(choose_group_levels(groups, mid, 1.0, covered), (std::vector<std::size_t>{0, 1, 1, 0}));
    EXPECT_EQ(groups_standing_in(groups), (std::vector<std::uint8_t>{0, 0, 0, 0}));
    groups[1].levels = none;  // dropped by a change, rebuilt later
    groups[1].levels_waiting = true;
    EXPECT_EQ(groups_standing_in(groups), (std::vector<std::uint8_t>{1, 0, 0, 0}));
    EXPECT_EQ(choose_group_levels(groups, mid, 1.0, covered), (std::vector<std::size_t>{1, 0, 0, 0}));
    EXPECT_EQ(covered, (std::vector<std::uint8_t>{0, 1, 1, 1}));
    EXPECT_TRUE(wants_detail(groups[0], 1, mid[0], 1.0, true));
    // A waiting grandchild makes its own parent stand in, not the root.
    groups[1].levels = child;
    groups[1].levels_waiting = false;
    groups[3].levels = none;
    groups[3].levels_waiting = true;
    EXPECT_EQ(groups_standing_in(groups), (std::vector<std::uint8_t>{0, 0, 1, 0}));
    const std::vector<double> near(4, 1500.0);  // every level but the grandchild's strays
    EXPECT_EQ(choose_group_levels(groups, near, 1.0, covered), (std::vector<std::size_t>{0, 0, 1, 0}));
    // A group without a level of its own cannot stand in: its children are drawn.
    groups[2].levels = none;
    EXPECT_EQ(choose_group_levels(groups, near, 1.0, covered), (std::vector<std::size_t>{0, 0, 0, 0}));
    // A child with no surface at its stride (built, nothing to draw) does not wait: the bound decides.
    groups[3].levels_waiting = false;
    groups[2].levels = child;
    EXPECT_EQ(choose_group_levels(groups, near, 1.0, covered), (std::vector<std::size_t>{0, 0, 0, 0}));
    groups[3].parent = 7;
    EXPECT_THROW(groups_standing_in(groups), Error);
}

// Four groups of one depth in a row along x (0-1-2-3): each level's own triangles join its x neighbours. A group
// draws only them when every joined neighbour is visible and draws its own coarse level too.
TEST(TileGroupLod, AGroupDrawsItsOwnTrianglesOnlyWhereEveryJoinedNeighbourDrawsItsOwn) {
    TriMesh tri;
    tri.positions = {Vec3(0.0), Vec3(1.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0)};
    tri.triangles = {{0, 1, 2}, {0, 2, 1}};
    constexpr int kLeft = 12, kRight = 14;  // slots of the neighbours at x - 1 and x + 1
    static_assert(kLeft == 9 + 3 + 0 && kRight == 9 + 3 + 2);
    const auto coarse = [&](std::uint32_t joins) { return TileMeshLevel{&tri, nullptr, nullptr, 1e-3, 1, joins}; };
    const std::vector<TileMeshLevel> ends_left{coarse(1u << kRight)}, middle{coarse((1u << kLeft) | (1u << kRight))},
        ends_right{coarse(1u << kLeft)}, simplified{TileMeshLevel{&tri, nullptr, nullptr, 1e-3}};
    std::vector<TileGroup> groups(4);
    groups[0].levels = ends_left;
    groups[1].levels = middle;
    groups[2].levels = middle;
    groups[3].levels = ends_right;
    for (std::size_t g = 0; g < 4; ++g) {
        if (g > 0) groups[g].neighbours[kLeft] = g - 1;
        if (g < 3) groups[g].neighbours[kRight] = g + 1;
    }
    const std::vector<std::uint8_t> all_seen(4, 1);
    using Own = std::vector<std::uint8_t>;
    EXPECT_EQ(groups_drawn_own_only(groups, std::vector<std::size_t>{1, 1, 1, 1}, all_seen), (Own{1, 1, 1, 1}));
    // Group 3 not drawn at its level (covered, or its tiles drawn): 2 keeps its ring and skirt, 1 and 0 need not.
    EXPECT_EQ(groups_drawn_own_only(groups, std::vector<std::size_t>{1, 1, 1, 0}, all_seen), (Own{1, 1, 0, 0}));
    // Group 1 hidden from the eye: its neighbours close themselves.
    EXPECT_EQ(groups_drawn_own_only(groups, std::vector<std::size_t>{1, 1, 1, 1}, Own{1, 0, 1, 1}), (Own{0, 1, 0, 1}));
    // A neighbour drawn at a simplified level (no own triangles) does not meet them exactly.
    groups[3].levels = simplified;
    EXPECT_EQ(groups_drawn_own_only(groups, std::vector<std::size_t>{1, 1, 1, 1}, all_seen), (Own{1, 1, 0, 0}));
    groups[3].levels = ends_right;
    // A joined neighbour that is missing (no group there) needs the ring; one not joined does not matter.
    groups[2].neighbours[kRight] = TileGroup::kNone;
    EXPECT_EQ(groups_drawn_own_only(groups, std::vector<std::size_t>{1, 1, 1, 1}, all_seen), (Own{1, 1, 0, 1}));
    groups[3].neighbours[kRight] = 0;  // not in its joins
    EXPECT_EQ(groups_drawn_own_only(groups, std::vector<std::size_t>{1, 1, 1, 1}, all_seen), (Own{1, 1, 0, 1}));
    EXPECT_THROW(groups_drawn_own_only(groups, std::vector<std::size_t>{1, 1, 1}, all_seen), Error);
    EXPECT_THROW(groups_drawn_own_only(groups, std::vector<std::size_t>{1, 2, 1, 1}, all_seen), Error);
    groups[1].neighbours[kLeft] = 9;
    EXPECT_THROW(groups_drawn_own_only(groups, std::vector<std::size_t>{1, 1, 1, 1}, all_seen), Error);
}

}  // namespace
}  // namespace tridex::renderer
