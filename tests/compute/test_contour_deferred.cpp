// Tests of the deferred contour of a stroke drawn coarse (compute/contour/deferred_contour.hpp): every tile it lets
// be drawn while others wait has the mesh a contour after every cut gives, bit for bit, and once none waits the whole
// contour equals that one, whichever way the tiles were contoured (oldest first, by group, with a later change).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/deferred_contour.hpp"
#include "compute/contour/startup_refine.hpp"
#include "compute/tools/boolean.hpp"
#include "core/error.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;

// Cut k of a groove across the sphere's +z cap: a ball of 10 cells swept over a fifth of the path each.
void cut(TriDexel& m, int k) {
    const Lattice& L = m.lattice;
    const auto at = [&](double u) {
        return L.to_world(kOffCentre + Vec3(-30.0 + 60.0 * u, 8.0 * u, kOffCentreRadius - 4.0));
    };
    subtract_capsule(m, Segment{at(k / 5.0), at((k + 1) / 5.0)}, 10.0 * L.cell_m);
}

// The model contoured after every cut, and the same cuts with a deferral.
struct Pair {
    TriDexel ref_model = off_centre_sphere(), model = off_centre_sphere();
    Contourer ref{ref_model}, contourer{model};
    DeferredContour deferral{model.tiles.tiles};
    std::set<std::uint64_t> deferred, visible;
    Pair() {
        ref.update(ref_model);
        contourer.update(model);
    }
    void cut_both(int k, bool defer) {
        cut(ref_model, k);
        ref.update(ref_model);
        cut(model, k);
        if (defer) {
            for (const std::uint64_t t : deferral.defer(model)) deferred.insert(t);
        } else {
            deferral.take_dirty(model);
            contourer.update(model);
        }
        take();
    }
    void take() {
        for (const std::uint64_t t : deferral.take_visible()) visible.insert(t);
    }
};

// Every tile the deferral lets be drawn has the reference's mesh, bit for bit; returns how many are hidden.
std::size_t expect_drawn_tiles_current(const Pair& p) {
    std::size_t hidden = 0;
    std::vector<std::uint8_t> ma, mb;
    for (std::size_t t = 0; t < p.ref.tile_count(); ++t) {
        if (p.deferral.hidden(t)) {
            ++hidden;
            continue;
        }
        EXPECT_EQ(p.contourer.tile_triangle_count(t), p.ref.tile_triangle_count(t)) << "tile " << t;
        if (p.ref.tile_triangle_count(t) == 0) continue;
        const TriMesh a = p.contourer.tile_mesh(t, ma), b = p.ref.tile_mesh(t, mb);
        EXPECT_EQ(a.positions, b.positions) << "tile " << t;
        EXPECT_EQ(a.triangles, b.triangles) << "tile " << t;
    }
    return hidden;
}

void expect_same_contour(const Pair& p) {
    EXPECT_EQ(p.deferral.count(), 0u);
    const TriMesh a = p.contourer.mesh(), b = p.ref.mesh();
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.triangles, b.triangles);
    for (const std::uint64_t t : p.deferred) EXPECT_TRUE(p.visible.count(t)) << "tile " << t << " never reported";
}

TEST(DeferredContour, TilesContouredOldestFirstAreDrawnOnlyOnceTheirNeighboursAreCurrent) {
    Pair p;
    for (int k = 0; k < 3; ++k) p.cut_both(k, true);
    ASSERT_GT(p.deferral.count(), 20u);
    EXPECT_EQ(p.deferral.count(), p.deferred.size());
    EXPECT_EQ(expect_drawn_tiles_current(p), p.deferred.size());  // only the deferred tiles are hidden
    // A few at a time: tiles contoured next to ones still waiting stay hidden, and what is drawn is current.
    std::size_t batches = 0, partly = 0;
    while (p.deferral.count() > 0) {
        ASSERT_GT(p.deferral.contour_oldest(p.model, p.contourer, 7), 0u);
        p.take();
        const std::size_t hidden = expect_drawn_tiles_current(p);
        if (hidden > p.deferral.count()) ++partly;  // contoured, hidden behind a neighbour still waiting
        ++batches;
    }
    EXPECT_GT(batches, 3u);
    EXPECT_GT(partly, 0u);
    EXPECT_EQ(expect_drawn_tiles_current(p), 0u);
    expect_same_contour(p);
}

TEST(DeferredContour, AChangeContouredAtOnceTakesTheDeferredTilesItReaches) {
    Pair p;
    p.cut_both(0, true);
    p.cut_both(1, true);
    const std::size_t waiting = p.deferral.count();
    p.cut_both(2, false);  // the stroke closed: the next cut is contoured at once, with the waiting tiles it reaches
    EXPECT_LT(p.deferral.count(), waiting);
    EXPECT_GT(p.deferral.count(), 0u);  // the groove's start lies beyond the last cut's reach
    expect_drawn_tiles_current(p);
    p.deferral.contour_all(p.model, p.contourer);
    p.take();
    EXPECT_EQ(expect_drawn_tiles_current(p), 0u);
    expect_same_contour(p);
}

TEST(DeferredContour, AGroupAskedForIsDrawnWholeAtOnce) {
    Pair p;
    for (int k = 0; k < 4; ++k) p.cut_both(k, true);
    // The depth-2 group (4x4x4 tiles) holding the most deferred tiles.
    std::map<std::array<int, 3>, int> per_group;
    const std::array<int, 3> dims = p.model.tiles.tiles;
    for (const std::uint64_t t : p.deferred) {
        const int x = static_cast<int>(t % dims[0]), y = static_cast<int>(t / dims[0] % dims[1]),
                  z = static_cast<int>(t / (dims[0] * dims[1]));
        ++per_group[{x >> 2, y >> 2, z >> 2}];
    }
    const auto best = std::max_element(per_group.begin(), per_group.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    const std::array<int, 3> g = best->first;
    const std::size_t before = p.deferral.count();
    EXPECT_GE(p.deferral.contour_group(p.model, p.contourer, 2, g), static_cast<std::size_t>(best->second));
    EXPECT_LT(p.deferral.count(), before);
    p.take();
    for (int z = 4 * g[2]; z < 4 * g[2] + 4; ++z)
        for (int y = 4 * g[1]; y < 4 * g[1] + 4; ++y)
            for (int x = 4 * g[0]; x < 4 * g[0] + 4; ++x)
                EXPECT_FALSE(p.deferral.hidden(p.model.tiles.index(x, y, z))) << x << "," << y << "," << z;
    expect_drawn_tiles_current(p);
    // Out of range: nothing.
    EXPECT_EQ(p.deferral.contour_group(p.model, p.contourer, 7, g), 0u);
    EXPECT_EQ(p.deferral.contour_group(p.model, p.contourer, 2, {100, 0, 0}), 0u);
    p.deferral.contour_all(p.model, p.contourer);
    p.take();
    expect_same_contour(p);
}

// A coarse-first start-up's refinement beside a deferred stroke: each region it contours takes the deferred tiles next
// to it along (StartupRefiner::contour_beside), and every tile both let be drawn has the reference's mesh (a tile
// beside one never contoured is never drawn).
TEST(DeferredContour, AStartUpsRefinementBesideADeferredStrokeDrawsOnlyCurrentTiles) {
    Pair p;
    TriDexel fresh = off_centre_sphere();  // the deferral's model, not contoured yet: a coarse-first start-up
    Contourer contourer(fresh);
    StartupRefiner refiner(fresh, 1, fresh.lattice.to_world(Vec3(0.0)));
    DeferredContour deferral(fresh.tiles.tiles);
    refiner.contour_beside(&deferral);
    // The refinement has contoured part of the groove's tiles (the depth-2 group of tiles x 0-3, y 4-7, z 4-7, and
    // those within one tile of it), not the rest, when the stroke comes: its tiles there wait with an old contour,
    // start-up's beyond stay pending, and the regions contoured later meet both.
    EXPECT_GT(refiner.refine_group(fresh, contourer, 2, {0, 1, 1}), 0u);
    for (int k = 0; k < 3; ++k) {
        cut(p.ref_model, k);
        p.ref.update(p.ref_model);
        cut(fresh, k);
        deferral.defer(fresh);
    }
    ASSERT_GT(deferral.count(), 0u);
    const std::size_t waiting = deferral.count();
    std::vector<std::uint8_t> ma, mb;
    std::size_t checked = 0, regions = 0;
    const auto expect_current = [&] {
        for (std::size_t t = 0; t < p.ref.tile_count(); ++t) {
            if (!refiner.publishable(t) || deferral.hidden(t) || p.ref.tile_triangle_count(t) == 0) continue;
            const TriMesh a = contourer.tile_mesh(t, ma), b = p.ref.tile_mesh(t, mb);  // throws beside a stale tile
            EXPECT_EQ(a.positions, b.positions) << "tile " << t;
            EXPECT_EQ(a.triangles, b.triangles) << "tile " << t;
            ++checked;
        }
    };
    while (refiner.refine_next(fresh, contourer) > 0) {
        ++regions;
        if (regions % 8 == 0) expect_current();
    }
    expect_current();
    EXPECT_GT(checked, 100u);
    EXPECT_LT(deferral.count(), waiting);  // those beside the regions went with them
    deferral.contour_all(fresh, contourer);
    refiner.finish(fresh, contourer);
    const TriMesh a = contourer.mesh(), b = p.ref.mesh();
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.triangles, b.triangles);
}

TEST(DeferredContour, RefusesAModelOfAnotherGrid) {
    DeferredContour d({2, 2, 2});
    TriDexel m = off_centre_sphere();
    EXPECT_THROW(d.defer(m), Error);
}

}  // namespace
}  // namespace tridex::compute
