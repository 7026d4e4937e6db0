// Tests of the coarse-first start-up (compute/contour/startup_refine.hpp and TileSurfaceCache::expect_tiles): the first
// refresh holds no tile and every group over the whole model with the coarsest level; the tiles then replace it
// region by region and end equal, bit for bit, to a start-up that contoured everything first; a cut during the
// refinement is contoured at once and redraws the coarsest groups within its reach at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <memory>
#include <utility>

#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/refine_wanted.hpp"
#include "compute/contour/startup_refine.hpp"
#include "compute/tools/boolean.hpp"
#include "core/error.hpp"
#include "test_coarse_first_session.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;

const Vec3 kCentre = kOffCentre;  // grid units on a 128-cell cube lattice
constexpr double kRadius = kOffCentreRadius;
constexpr int kTop = CoarseLevelOptions{}.max_depth;
// A cut across the sphere's +x side, away from the lattice's origin corner where the refinement starts.
void cut(TriDexel& m) {
    const Lattice& L = m.lattice;
    const Vec3 a = L.to_world(kCentre + Vec3(kRadius, -10.0, 5.0)),
               b = L.to_world(kCentre + Vec3(kRadius - 3.0, 12.0, -4.0));
    subtract_capsule(m, Segment{a, b}, 6.0 * L.cell_m);
}

// The start-up that contours every tile before the first refresh.
struct Full {
    TriDexel model = sphere_model();
    Contourer contourer{model};
    TileSurfaceCache cache;
    Full() {
        contourer.update(model);
        use_coarse_lod(cache, model);
        cache.refresh(contourer);
        settle(cache);
    }
};

// Every group whose children cannot cover it yet has a level of its own, or lies under one that must be drawn, or
// has nothing to draw: a fresh read of `model` at its stride finds no surface in it.
void expect_no_hole(const TileSurfaceCache& cache, const TriDexel& model) {
    std::array<std::unique_ptr<CoarseGroupLevels>, kTop + 1> fresh;  // read once per depth, when needed
    for (const TileGroupSurface& g : cache.groups())
        if (!g.children_cover && g.lods.empty()) {
            const TileGroupSurface* p = nullptr;
            for (const TileGroupSurface& q : cache.groups())
                if (q.id == g.parent) p = &q;
            ASSERT_NE(p, nullptr) << "a top group " << g.id << " with nothing under it and no level";
            if (!p->children_cover) continue;
            ASSERT_LE(g.depth, kTop);
            if (!fresh[g.depth])
                fresh[g.depth] = std::make_unique<CoarseGroupLevels>(model, CoarseLevelOptions{}, g.depth);
            EXPECT_TRUE(fresh[g.depth]->level(g.depth, g.coords).mesh.triangles.empty())
                << "group " << g.id << " at depth " << g.depth << " has a surface, no level and nothing drawn over it";
        }
}

// Every depth-`depth` group with a level has the one a fresh read of `model` at that stride gives; returns how many.
std::size_t expect_levels_as_read(const TileSurfaceCache& cache, const TriDexel& model,
                                  const CoarseLevelOptions& levels, int depth) {
    const CoarseGroupLevels fresh(model, levels, depth);
    std::size_t compared = 0;
    for (const TileGroupSurface& g : cache.groups()) {
        if (g.depth != depth || g.lods.empty()) continue;
        EXPECT_EQ(g.lods[0].mesh.positions, fresh.level(depth, g.coords).mesh.positions) << g.id;
        ++compared;
    }
    return compared;
}

void expect_same_surface(const TileSurfaceCache& a, const TileSurfaceCache& b) {
    ASSERT_EQ(a.tiles().size(), b.tiles().size());
    for (std::size_t i = 0; i < a.tiles().size(); ++i) {
        const TileSurface& x = a.tiles()[i];
        const TileSurface& y = b.tiles()[i];
        ASSERT_EQ(x.id, y.id);
        EXPECT_EQ(x.mesh.positions, y.mesh.positions) << "tile " << x.id;
        EXPECT_EQ(x.mesh.triangles, y.mesh.triangles) << "tile " << x.id;
        EXPECT_EQ(x.materials, y.materials) << "tile " << x.id;
    }
    ASSERT_EQ(a.groups().size(), b.groups().size());
    for (std::size_t i = 0; i < a.groups().size(); ++i) {
        const TileGroupSurface& x = a.groups()[i];
        const TileGroupSurface& y = b.groups()[i];
        ASSERT_EQ(x.id, y.id);
        EXPECT_EQ(x.children, y.children) << "group " << x.id;
        EXPECT_TRUE(x.children_cover && y.children_cover) << "group " << x.id;
        ASSERT_EQ(x.lods.size(), y.lods.size()) << "group " << x.id;
        for (std::size_t k = 0; k < x.lods.size(); ++k) {
            EXPECT_EQ(x.lods[k].mesh.positions, y.lods[k].mesh.positions) << "group " << x.id;
            EXPECT_EQ(x.lods[k].mesh.triangles, y.lods[k].mesh.triangles) << "group " << x.id;
            EXPECT_EQ(x.lods[k].error_m, y.lods[k].error_m) << "group " << x.id;
        }
    }
}

TEST(CoarseFirst, TheFirstRefreshHoldsEveryGroupAtTheCoarsestLevelOverTheWholeModel) {
    CoarseFirst s;
    const Full full;
    EXPECT_TRUE(s.cache.tiles().empty()) << "no tile is contoured before the first mesh";
    EXPECT_GT(s.refiner->pending(), 0u);
    EXPECT_EQ(s.cache.expected_tiles(), s.refiner->pending());
    // Every group of a full start-up (and some over tiles next to the surface that will turn out empty); the coarsest
    // depth drawn everywhere, the finer ones not read yet.
    for (const TileGroupSurface& f : full.cache.groups()) {
        bool found = false;
        for (const TileGroupSurface& g : s.cache.groups()) found = found || g.id == f.id;
        EXPECT_TRUE(found) << f.id;
    }
    Aabb coarse_box;
    std::size_t coarse_triangles = 0, top = 0;
    for (std::size_t i = 0; i < s.cache.groups().size(); ++i) {
        const TileGroupSurface& g = s.cache.groups()[i];
        if (g.depth < kTop) {
            EXPECT_TRUE(g.lods.empty()) << g.id;
            EXPECT_FALSE(g.children_cover) << g.id;
            continue;
        }
        ++top;
        ASSERT_EQ(g.lods.size(), 1u) << g.id;
        EXPECT_FALSE(g.children_cover) << "nothing under group " << g.id << " can stand in for it yet";
        coarse_triangles += g.lods[0].mesh.triangles.size();
        coarse_box.add(g.lods[0].mesh.bounds().lo);
        coarse_box.add(g.lods[0].mesh.bounds().hi);
    }
    EXPECT_GE(top, 1u);
    expect_no_hole(s.cache, s.model);
    // They cover the whole model: the coarse levels' box is the full contour's within two cells, in a sixteenth
    // of its triangles (rings and skirts included).
    const TriMesh whole = full.contourer.mesh();
    const Aabb box = whole.bounds();
    const double h = s.model.lattice.cell_m;
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(coarse_box.lo[a], box.lo[a], 2.0 * h) << "axis " << a;
        EXPECT_NEAR(coarse_box.hi[a], box.hi[a], 2.0 * h) << "axis " << a;
    }
    EXPECT_LT(16 * coarse_triangles, whole.triangles.size());
}

TEST(CoarseFirst, RefinementEndsWithTheTilesAndLevelsOfAFullStartUpBitForBit) {
    CoarseFirst s;
    const Full full;
    while (s.cache.build_coarse_depth()) {}
    // Region by region: tiles arrive, and every group keeps something drawn over its part of the model.
    std::size_t regions = 0, last = 0;
    while (s.refiner->refine_next(s.model, s.contourer) > 0) {
        s.refresh();
        ++regions;
        EXPECT_GE(s.cache.tiles().size(), last);
        last = s.cache.tiles().size();
        expect_no_hole(s.cache, s.model);
    }
    EXPECT_GT(regions, 1u);
    EXPECT_TRUE(s.refiner->done());
    s.refresh();
    settle(s.cache);
    EXPECT_EQ(s.cache.expected_tiles(), 0u);
    expect_same_surface(s.cache, full.cache);
    EXPECT_EQ(s.contourer.mesh().positions, full.contourer.mesh().positions);
}

TEST(CoarseFirst, ACutDuringRefinementRedrawsTheCoarsestGroupsAtOnceAndEndsAsAFullStartUpWould) {
    CoarseFirst s;
    while (s.cache.build_coarse_depth()) {}
    settle(s.cache);  // the finer depths' levels, as the sculpt thread's idle passes take them in
    ASSERT_GT(s.refiner->refine_next(s.model, s.contourer), 0u);
    s.refresh();
    const std::size_t pending = s.refiner->pending();
    cut(s.model);
    const std::vector<std::uint32_t> dirty = s.model.tiles.dirty_tiles();
    ASSERT_FALSE(dirty.empty());
    s.contour_change();
    EXPECT_LT(s.refiner->pending(), pending);
    // The cut's tiles are contoured at once, and the coarsest groups within reach of it are rebuilt from the cut
    // model at once: each level equals a fresh read of the cut model at that stride. The depth-1 groups the cut
    // reaches get all their tiles, so no group over a cut tile must be drawn whatever its error: the cut is drawn at
    // full resolution wherever the view needs it.
    for (const std::uint32_t t : dirty) {
        if (s.contourer.tile_triangle_count(t) == 0) continue;
        bool found = false;
        for (const TileSurface& tile : s.cache.tiles()) found = found || tile.id == t;
        EXPECT_TRUE(found) << "tile " << t;
    }
    EXPECT_GT(expect_levels_as_read(s.cache, s.model, CoarseLevelOptions{}, kTop), 0u);
    const std::array<int, 3> dims = s.contourer.tile_dims();
    for (const TileGroupSurface& g : s.cache.groups()) {
        if (g.children_cover) continue;
        const int span = 1 << g.depth;
        for (const std::uint32_t t : dirty) {
            const std::array<int, 3> c{static_cast<int>(t % dims[0]), static_cast<int>(t / dims[0] % dims[1]),
                                       static_cast<int>(t / (dims[0] * dims[1]))};
            EXPECT_FALSE(c[0] / span == g.coords[0] && c[1] / span == g.coords[1] && c[2] / span == g.coords[2])
                << "group " << g.id << " at depth " << g.depth << " stands in over cut tile " << t;
        }
    }
    expect_no_hole(s.cache, s.model);
    s.refine_all();
    Full full;
    cut(full.model);
    full.contourer.update(full.model);
    full.cache.refresh(full.contourer);
    settle(full.cache);
    expect_same_surface(s.cache, full.cache);
}

// Levels of a depth read later that must contour their coarse tiles first wait while a stroke is open (the others,
// which only read, are built); between strokes each pass builds at least one of them, until none waits.
TEST(CoarseFirst, LevelsThatContourTheirCoarseTilesWaitWhileAStrokeIsOpen) {
    CoarseFirst s;
    while (s.cache.build_coarse_depth()) {}
    ASSERT_GT(s.cache.coarse_waiting(), 0u);
    for (int i = 0; i < 20; ++i) s.cache.collect_lods(true);  // more passes than the levels that only read need
    const std::size_t during = s.cache.coarse_waiting();
    EXPECT_GT(during, 0u) << "no level of a depth read later can be built without contouring";
    for (int i = 0; i < 20; ++i) s.cache.collect_lods(true);
    EXPECT_EQ(s.cache.coarse_waiting(), during) << "a pass during a stroke contoured coarse tiles";
    s.cache.collect_lods(false);
    EXPECT_LT(s.cache.coarse_waiting(), during);
    settle(s.cache);
}

// Two spheres on a 384 x 128 x 128-cell lattice, in the first and the last of its three depth-3 groups along x.
TriDexel two_spheres() {
    Lattice L = cube_lattice(128);
    L.cells[0] = 384;
    TriDexel m = empty_model(L);
    fill_rays(m, [&](int a, int u, int v) {
        std::vector<Interval> ray = sphere_chord(kCentre, kRadius, a, u, v);
        for (const Interval& i : sphere_chord(kCentre + Vec3(256.0, 0.0, 0.0), kRadius, a, u, v)) ray.push_back(i);
        return ray;  // along x the first sphere's chord comes first
    });
    return m;
}

// Coarse levels down to kDeferredCoarseDepth, one depth under the coarsest, as the sessions' (the stroke's depth then
// is not the coarsest).
CoarseLevelOptions to_stroke_depth() {
    CoarseLevelOptions levels;
    levels.max_depth = TileSurfaceCache::kDeferredCoarseDepth + 1;
    return levels;
}

// The first depth-d group at group coordinate x.
const TileGroupSurface& group_at(const TileSurfaceCache& cache, int d, int x) {
    for (const TileGroupSurface& g : cache.groups())
        if (g.depth == d && g.coords[0] == x) return g;
    throw Error("no such group");
}

// Depth-d groups at group coordinate x whose level still waits.
std::vector<std::uint64_t> waiting(const TileSurfaceCache& cache, int depth, int x) {
    std::vector<std::uint64_t> ids;
    for (const TileGroupSurface& g : cache.groups())
        if (g.depth == depth && g.coords[0] == x && g.lods.empty()) ids.push_back(g.id);
    return ids;
}

// What SculptThread does with a step while a stroke is drawn coarse: the change's tiles are deferred, then refreshed.
void defer_cut(CoarseFirst& s, const Vec3& offset) {
    const Lattice& L = s.model.lattice;
    const Vec3 a = L.to_world(kCentre + offset + Vec3(kRadius, -10.0, 5.0));
    const Vec3 b = L.to_world(kCentre + offset + Vec3(kRadius - 3.0, 12.0, -4.0));
    subtract_capsule(s.model, Segment{a, b}, 6.0 * L.cell_m);
    const std::vector<std::uint32_t> d = s.model.tiles.dirty_tiles();
    ASSERT_FALSE(d.empty());
    s.model.clear_dirty();
    s.cache.defer_tiles(std::vector<std::uint64_t>(d.begin(), d.end()));
    s.refresh();
}

// A stroke drawn coarse (defer_tiles) rebuilds at once the waiting levels down to kDeferredCoarseDepth of the groups
// within its reach, which draw it, and leaves the other waiting levels of start-up's finer depths to settle between
// strokes.
TEST(CoarseFirst, AStrokeDrawnCoarseRebuildsOnlyTheWaitingLevelsWithinItsReach) {
    const int depth = TileSurfaceCache::kDeferredCoarseDepth;
    ASSERT_EQ(depth, 3) << "the two spheres lie in two groups of this depth";
    CoarseFirst s(two_spheres(), to_stroke_depth());  // the depth-3 levels wait for their depth's read
    while (s.cache.build_coarse_depth()) {}
    const std::vector<std::uint64_t> far = waiting(s.cache, depth, 0), near = waiting(s.cache, depth, 2);
    ASSERT_FALSE(far.empty());
    ASSERT_FALSE(near.empty());
    defer_cut(s, Vec3(256.0, 0.0, 0.0));  // the second sphere's +x side: far from the group at x = 0
    EXPECT_EQ(waiting(s.cache, depth, 0), far) << "a level out of the stroke's reach was rebuilt during it";
    EXPECT_LT(waiting(s.cache, depth, 2).size(), near.size()) << "no level within the stroke's reach was rebuilt";
}

// A slab with a fin on it (40 cells tall; by default y 60.3 .. 63.7), on a 128-cell cube lattice: the depth-1 rays
// (every 2nd) see the default fin, the depth-3 ones (every 8th) miss it; one to y 61.7 holds node 61 alone: all miss.
TriDexel slab_with_fin(double fin_hi_y = 63.7) {
    TriDexel m = empty_model(cube_lattice(128));
    fill_rays(m, [fin_hi_y](int a, int u, int v) {
        std::vector<Interval> ray = box_chord(Vec3(20.5, 20.5, 20.5), Vec3(107.5, 107.5, 60.5), a, u, v);
        for (const Interval& i : box_chord(Vec3(40.5, 60.3, 60.5), Vec3(87.5, fin_hi_y, 100.5), a, u, v)) {
            if (!ray.empty() && i.enter <= ray.back().exit)
                ray.back().exit = std::max(ray.back().exit, i.exit);
            else
                ray.push_back(i);
        }
        return ray;
    });
    return m;
}

// A coarse-first start-up's depth-3 level misses the fin: once the depth-1 levels are built, its error estimate is
// raised from them to about the fin's height, far over a quarter of its coarse cell; a change within its reach
// rebuilds it at once, and the new level keeps that error until it is estimated again.
TEST(CoarseFirst, ADeepLevelsEstimateSeesAThinFeatureItsStrideMissesAndKeepsItWhenRebuilt) {
    CoarseFirst s(slab_with_fin());
    while (s.cache.build_coarse_depth()) {}
    settle(s.cache);
    const auto top_error = [&] {
        for (const TileGroupSurface& g : s.cache.groups())
            if (g.depth == kTop && !g.lods.empty()) return g.lods[0].error_m;
        return -1.0;
    };
    const double cell = s.model.lattice.cell_m, flat = TileSurfaceCache::kStartupErrorCoarseCells * cell * (1 << kTop);
    const double raised = top_error();
    std::printf(
        "[coarse first] depth-%d estimate with a fin its stride misses: %.1f cells (a quarter coarse cell: %.1f)\n",
        kTop, raised / cell, flat / cell);
    EXPECT_GT(raised, 20.0 * cell) << "the estimate did not see the fin";
    const Lattice& L = s.model.lattice;
    subtract_capsule(s.model, Segment{L.to_world(Vec3(25.0, 25.0, 62.0)), L.to_world(Vec3(30.0, 25.0, 62.0))},
                     3.0 * cell);
    s.contour_change();
    EXPECT_GE(top_error(), raised) << "the rebuilt level forgot the fin";
}

// A start-up measures a finest level built before its tiles against the model's own surface points in its box (its
// rays' ends), and names the finest groups whose read missed their surface. On a fin 1.4 cells thick (no coarse ray
// sees it): the levels at its foot measure its step, over 2 cells (half a cell was taken before), the slab's stay
// under that; the groups over the fin have no level and are named, and contouring them as wanted brings it in.
TEST(CoarseFirst, AFinestLevelBeforeItsTilesIsMeasuredAgainstTheModelsOwnSurfacePoints) {
    CoarseFirst s(slab_with_fin(61.7));
    while (s.cache.build_coarse_depth()) {}
    settle(s.cache);
    ASSERT_GT(s.refiner->pending(), 0u) << "the tiles came in: the levels were measured against them";
    const double cell = s.model.lattice.cell_m, quarter = TileSurfaceCache::kStartupErrorCoarseCells * 2.0 * cell;
    double foot = 0.0, flat = 0.0;
    std::vector<std::uint64_t> over_fin;  // depth 1: x 32 .. 96, y 32 .. 64, z 64 .. 128 cells
    for (const TileGroupSurface& g : s.cache.groups()) {
        const std::array<int, 3>& c = g.coords;
        if (g.depth == 1 && (c[0] == 1 || c[0] == 2) && c[1] == 1 && c[2] >= 2) over_fin.push_back(g.id);
        if (g.depth != 1 || g.lods.empty()) continue;
        if (c[1] == 1 && c[2] == 1) foot = std::max(foot, g.lods[0].error_m);
        if (c == std::array<int, 3>{1, 2, 1}) flat = g.lods[0].error_m;  // the slab's top face alone
    }
    std::sort(over_fin.begin(), over_fin.end());
    const std::vector<std::uint64_t> missed = s.cache.missed_surface_groups();
    std::printf(
        "[coarse first] depth-1 levels before their tiles: %.2f cells at the fin's foot, %.2f on the slab; "
        "%zu groups missed the fin\n",
        foot / cell, flat / cell, missed.size());
    EXPECT_GT(foot, 2.0 * cell) << "the level's error did not see the fin's foot";
    EXPECT_LT(flat, quarter);
    EXPECT_FALSE(over_fin.empty());
    EXPECT_EQ(missed, over_fin);
    const WantedRefined n = refine_wanted_groups(missed, s.cache.groups(), s.model, s.contourer, s.refiner.get(),
                                                 nullptr, kWantedBlockDepth, [] { return true; });
    s.refresh();
    EXPECT_TRUE(n.startup > 0 && s.cache.missed_surface_groups().empty()) << n.startup;
    for (const TileGroupSurface& g : s.cache.groups())
        EXPECT_TRUE(!std::binary_search(over_fin.begin(), over_fin.end(), g.id) || g.children_cover) << g.id;
}

// A caller whose frames hold no stroke's samples (a cluster render rank, TileSurfaceCache::build_away_from_changes)
// builds the waiting levels of start-up's finer depths out of a change's reach while tiles keep changing in every
// refresh; by default they wait until no tile has changed for the worker's group_settle_s. Those within reach wait
// either way.
TEST(CoarseFirst, LevelsAwayFromChangesAreBuiltWhileTilesKeepChangingWhenAsked) {
    const int depth = TileSurfaceCache::kDeferredCoarseDepth - 1;
    for (const bool away : {false, true}) {
        CoarseFirst s(two_spheres(), to_stroke_depth());
        // The fixture has refreshed once: a second cache, as the fixture's, with a worker whose groups never settle.
        TileSurfaceCache cache;
        TileLodOptions o;
        o.cell_m = s.model.lattice.cell_m;
        cache.enable_lod(o);
        cache.use_coarse_groups(s.model, to_stroke_depth(), true);
        cache.expect_tiles(s.refiner->pending_tiles());
        LodWorkerOptions w;
        w.lod = o;
        w.threads = 1;
        w.group_settle_s = 10.0;  // the most it takes: longer than the test
        cache.build_lods_in_background(w);
        cache.build_away_from_changes(away);
        cache.refresh(StartupRefiner::Source(s.contourer, *s.refiner));
        while (cache.build_coarse_depth()) {}
        const std::vector<std::uint64_t> far = waiting(cache, depth, 0), near = waiting(cache, depth, 5);
        ASSERT_FALSE(far.empty());
        ASSERT_FALSE(near.empty());
        for (int i = 0; i < 6; ++i) {  // the second sphere cut a little deeper in every refresh
            const Lattice& L = s.model.lattice;
            const Vec3 c = kCentre + Vec3(256.0 + kRadius - i, 0.0, 0.0);
            subtract_capsule(s.model, Segment{L.to_world(c - Vec3(0.0, 8.0, 0.0)), L.to_world(c + Vec3(0.0, 8.0, 0.0))},
                             4.0 * L.cell_m);
            const std::vector<std::uint32_t> d = s.model.tiles.dirty_tiles();
            const std::vector<std::uint64_t> dirty(d.begin(), d.end());
            cache.stop_expecting(s.refiner->pending_among(dirty));
            s.refiner->contour_with_change(s.model, dirty);
            s.contourer.update(s.model);
            cache.arrive(s.refiner->take_newly_publishable());
            cache.refresh(StartupRefiner::Source(s.contourer, *s.refiner));
            for (int k = 0; k < 20; ++k) cache.collect_lods();
        }
        if (away) {
            EXPECT_TRUE(waiting(cache, depth, 0).empty())
                << "a level out of the changes' reach waited for them to settle";
            // Those built are the model's as it is now: out of reach, the changes do not touch them.
            EXPECT_GT(expect_levels_as_read(cache, s.model, to_stroke_depth(), depth), 0u);
        } else {
            EXPECT_EQ(waiting(cache, depth, 0), far) << "a level was built before the changes settled";
        }
        EXPECT_FALSE(waiting(cache, depth, 5).empty()) << "every level within the changes' reach was built";
    }
}

// A change outside a stroke (an undo's) re-reads the coarsest model at once and the finer ones once it settles. A
// stroke that starts before then rebuilds its depth's levels from a model that holds that change too.
TEST(CoarseFirst, AStrokeBeforeAChangeSettledDrawsThatChangeToo) {
    const int depth = TileSurfaceCache::kDeferredCoarseDepth;
    const CoarseLevelOptions levels = to_stroke_depth();
    CoarseFirst s(sphere_model(), levels);
    s.refine_all();
    cut(s.model);  // the sphere's +x side, contoured at once
    s.contour_change();
    defer_cut(s, Vec3(-2.0 * kRadius, 0.0, 0.0));  // its -x side, in the same depth-3 group
    EXPECT_GT(expect_levels_as_read(s.cache, s.model, levels, depth), 0u);
}

// During a stroke drawn coarse, a level under a group the frames drew within the bound (frames_drew) waits for the
// stroke to settle: the frames draw that group in its place. Elsewhere the stroke's levels are rebuilt at once, and
// the coarsest depth's always.
TEST(CoarseFirst, AStrokeDrawnCoarseLeavesTheLevelsUnderAGroupTheFramesDrewForLater) {
    const int depth = TileSurfaceCache::kDeferredCoarseDepth;
    const CoarseLevelOptions levels = to_stroke_depth();
    for (const bool drawn : {false, true}) {
        SCOPED_TRACE(drawn ? "the parent drawn" : "another group drawn");
        CoarseFirst s(two_spheres(), levels);
        s.refine_all();
        const TileGroupSurface& top = group_at(s.cache, depth + 1, 1);  // over the second sphere
        ASSERT_EQ(group_at(s.cache, depth, 2).parent, top.id);
        s.cache.frames_drew({drawn ? top.id : group_at(s.cache, depth + 1, 0).id});
        defer_cut(s, Vec3(256.0, 0.0, 0.0));
        const TileGroupSurface& child = group_at(s.cache, depth, 2);
        EXPECT_FALSE(group_at(s.cache, depth + 1, 1).levels_waiting) << "the coarsest level waits";
        EXPECT_FALSE(group_at(s.cache, depth + 1, 1).lods.empty());
        EXPECT_EQ(child.levels_waiting, drawn);
        EXPECT_EQ(child.lods.empty(), drawn);
        settle(s.cache);  // the stroke is over: its waiting levels come
        EXPECT_FALSE(group_at(s.cache, depth, 2).levels_waiting);
        EXPECT_FALSE(group_at(s.cache, depth, 2).lods.empty());
    }
}

// A stroke's step whose finer levels all wait under groups the frames drew reads its change at the coarsest depth
// only. A later step that rebuilds a finer level reads the earlier steps' changes at that depth too.
TEST(CoarseFirst, AStrokeStepRebuildingAFinerLevelReadsTheChangesEarlierStepsLeft) {
    const int depth = TileSurfaceCache::kDeferredCoarseDepth;
    const CoarseLevelOptions levels = to_stroke_depth();
    CoarseFirst s(two_spheres(), levels);
    s.refine_all();
    s.cache.frames_drew({group_at(s.cache, depth + 1, 1).id});  // over the second sphere
    defer_cut(s, Vec3(256.0, 0.0, 0.0));                        // its level at depth 3 waits
    s.cache.frames_drew({group_at(s.cache, depth + 1, 0).id});
    defer_cut(s, Vec3(256.0 - 2.0 * kRadius, 0.0, 0.0));  // the sphere's other side, in the same depth-3 group
    EXPECT_GT(expect_levels_as_read(s.cache, s.model, levels, depth), 0u);
}

// During a stroke drawn coarse, the levels under kDeferredCoarseDepth wait, except under the groups a frame asks
// finer ones for (want_detail): those are rebuilt with the next refresh, up to kDeferredDetailLevels.
TEST(CoarseFirst, AStrokeDrawnCoarseIsDrawnFinerWhereAFrameAsks) {
    const int depth = TileSurfaceCache::kDeferredDetailDepth;
    ASSERT_EQ(depth + 1, TileSurfaceCache::kDeferredCoarseDepth);
    CoarseFirst s;
    while (s.cache.build_coarse_depth()) {}
    const auto all = [&] {
        std::vector<std::uint64_t> ids = waiting(s.cache, depth, 0), more = waiting(s.cache, depth, 1);
        ids.insert(ids.end(), more.begin(), more.end());
        return ids;
    };
    const std::vector<std::uint64_t> before = all();
    ASSERT_FALSE(before.empty());
    ASSERT_LE(before.size(), TileSurfaceCache::kDeferredDetailLevels);
    defer_cut(s, Vec3(0.0));
    EXPECT_EQ(all(), before) << "a level finer than the stroke's depth was rebuilt though no frame asked";
    std::vector<std::uint64_t> top;
    for (const TileGroupSurface& g : s.cache.groups())
        if (g.depth == depth + 1) top.push_back(g.id);
    ASSERT_EQ(top.size(), 1u);
    s.cache.want_detail(top);
    defer_cut(s, Vec3(0.0, 0.0, -3.0));
    EXPECT_TRUE(all().empty()) << all().size() << " of the asked group's " << before.size() << " levels still wait";
    for (const TileGroupSurface& g : s.cache.groups())
        if (g.depth == depth && !g.lods.empty()) {
            EXPECT_GT(g.lods.front().error_m, 0.0) << g.id;
        }
}

// Levels a frame asks for again in a later step of the same stroke read the tiles that step changed again, though
// the earlier step read them at that depth already (only tiles unchanged since are skipped).
TEST(CoarseFirst, AFinerLevelAskedForAgainReadsTheTilesChangedSinceItsLastRead) {
    const int depth = TileSurfaceCache::kDeferredDetailDepth;
    CoarseFirst s;
    while (s.cache.build_coarse_depth()) {}
    std::vector<std::uint64_t> top;
    for (const TileGroupSurface& g : s.cache.groups())
        if (g.depth == depth + 1) top.push_back(g.id);
    ASSERT_EQ(top.size(), 1u);
    s.cache.want_detail(top);
    defer_cut(s, Vec3(0.0));
    const std::size_t first = expect_levels_as_read(s.cache, s.model, CoarseLevelOptions{}, depth);
    ASSERT_GT(first, 0u);
    s.cache.want_detail(top);
    defer_cut(s, Vec3(0.0, 0.0, -3.0));  // the same tiles again
    EXPECT_EQ(expect_levels_as_read(s.cache, s.model, CoarseLevelOptions{}, depth), first);
}

TEST(CoarseFirst, RefinerRefusesBadInputAndFinishesEverything) {
    TriDexel m = sphere_model();
    EXPECT_THROW(StartupRefiner(m, 0, Vec3(0.0)), Error);
    EXPECT_THROW(StartupRefiner(m, 7, Vec3(0.0)), Error);
    Contourer c(m);
    StartupRefiner r(m, kTop, Vec3(0.0));
    EXPECT_TRUE(m.tiles.dirty_tiles().empty()) << "the refiner owns the tiles to contour";
    const std::size_t n = r.pending();
    EXPECT_EQ(r.finish(m, c), n);
    EXPECT_TRUE(r.done());
    EXPECT_EQ(r.refine_next(m, c), 0u);
    for (std::size_t t = 0; t < c.tile_count(); ++t) EXPECT_TRUE(r.publishable(t));
    TileSurfaceCache cache;
    EXPECT_THROW(cache.expect_tiles({1}), Error);  // no coarse groups
}

}  // namespace
}  // namespace tridex::compute
