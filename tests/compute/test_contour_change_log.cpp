// Tests of the tile change records (compute/contour/tile_change_log.hpp) and of TileSurfaceCache::refresh visiting
// only the tiles its source says may have changed: through a start-up's refinement and a stroke's deferral, a cache
// refreshed after every step holds what a cache refreshed once, over every tile, holds.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/deferred_contour.hpp"
#include "compute/contour/held_tiles.hpp"
#include "compute/contour/startup_refine.hpp"
#include "compute/contour/tile_change_log.hpp"
#include "compute/tools/boolean.hpp"
#include "core/error.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;

TEST(TileChangeLog, ListsTheTilesAfterAMarkAndRefusesAMarkItNoLongerCovers) {
    const std::uint64_t before = fresh_tile_version();
    TileChangeLog log;
    std::vector<std::uint64_t> out;
    EXPECT_FALSE(log.since(before, out)) << "a mark from before the log was made";
    const std::uint64_t start = fresh_tile_version();
    log.add(fresh_tile_version(), 7);
    const std::uint64_t middle = fresh_tile_version();
    const std::uint64_t stamp = fresh_tile_version();
    log.add(stamp, 3);
    log.add(stamp, 7);
    ASSERT_TRUE(log.since(start, out));
    EXPECT_EQ(out, (std::vector<std::uint64_t>{7, 3, 7}));
    out.clear();
    ASSERT_TRUE(log.since(middle, out));
    EXPECT_EQ(out, (std::vector<std::uint64_t>{3, 7}));
    out.clear();
    ASSERT_TRUE(log.since(fresh_tile_version(), out));
    EXPECT_TRUE(out.empty());
    for (std::size_t i = 0; i < TileChangeLog::kMaxEntries; ++i) log.add(fresh_tile_version(), i);
    EXPECT_FALSE(log.since(middle, out)) << "its entries after the mark were dropped";
    EXPECT_TRUE(out.empty());
    const std::uint64_t late = fresh_tile_version();
    log.add(fresh_tile_version(), 1);
    ASSERT_TRUE(log.since(late, out));
    EXPECT_EQ(out, (std::vector<std::uint64_t>{1}));
    EXPECT_NE(log.id(), TileChangeLog().id());
    // A copy changes apart from its original from now on: a record of its own, which knows nothing from before.
    const TileChangeLog copy = log;
    EXPECT_NE(copy.id(), log.id());
    EXPECT_FALSE(copy.since(late, out));
    EXPECT_EQ(TileChangeLog::entries_for(10), 4096u);
    EXPECT_EQ(TileChangeLog::entries_for(100000), 200000u);
    EXPECT_EQ(TileChangeLog::entries_for(std::size_t{1} << 30), TileChangeLog::kMaxEntries);
    TileChangeLog small(4);
    const std::uint64_t mark = fresh_tile_version();
    for (std::uint64_t t = 0; t < 4; ++t) small.add(fresh_tile_version(), t);
    out.clear();
    EXPECT_TRUE(small.since(mark, out));
    EXPECT_EQ(out.size(), 4u);
    small.add(fresh_tile_version(), 9);  // full: the older half goes
    EXPECT_FALSE(small.since(mark, out));
}

// The same tiles, versions and meshes in both caches.
void expect_same_tiles(const TileSurfaceCache& a, const TileSurfaceCache& b) {
    ASSERT_EQ(a.tiles().size(), b.tiles().size());
    for (std::size_t i = 0; i < a.tiles().size(); ++i) {
        const TileSurface& x = a.tiles()[i];
        const TileSurface& y = b.tiles()[i];
        ASSERT_EQ(x.id, y.id);
        EXPECT_EQ(x.source_version, y.source_version) << "tile " << x.id;
        EXPECT_EQ(x.mesh.positions, y.mesh.positions) << "tile " << x.id;
        EXPECT_EQ(x.normals, y.normals) << "tile " << x.id;
    }
}

// Strokes deferred and their tiles contoured later, changes contoured at once (beside them and away from them), with
// a coarse-first start-up refined region by region (`startup`) or after it; the cache refreshed through the held
// tiles (as the sculpt thread does) after every step, and compared with a cache that reads every tile once.
void run_session(bool startup) {
    TriDexel model = off_centre_sphere();
    Contourer contourer(model);
    std::unique_ptr<StartupRefiner> refiner;
    if (startup)
        refiner = std::make_unique<StartupRefiner>(model, 1, model.lattice.to_world(Vec3(0.0)));
    else
        contourer.update(model);
    DeferredContour deferral(model.tiles.tiles);
    if (refiner) refiner->contour_beside(&deferral);
    TileSurfaceCache cache;
    std::size_t visits = 0, refreshes = 0, first = 0;
    const auto check = [&] {
        refresh_held_tiles(cache, contourer, refiner.get(), &deferral);
        if (refreshes++ > 0) visits += cache.last_refresh_visits();  // the first reads every tile
        TileSurfaceCache whole;                                      // every tile read once, through the same view
        if (refiner) {
            const StartupRefiner::Source source(contourer, *refiner);
            whole.refresh(DeferredContour::Source(source, deferral));
        } else {
            whole.refresh(DeferredContour::Source(ContourerTiles(contourer), deferral));
        }
        expect_same_tiles(cache, whole);
        if (refreshes == 1) first = cache.tiles().size();
    };
    check();
    for (int step = 0; step < 24; ++step) {
        SCOPED_TRACE("step " + std::to_string(step));
        if (refiner && step % 3 == 0) refiner->refine_next(model, contourer);
        if (step % 4 == 1) {  // a stroke's step: deferred
            groove_cut(model, step / 4);
            deferral.defer(model);
        }
        if (step % 4 == 3) deferral.contour_oldest(model, contourer, 5);  // between strokes
        if (step % 8 == 6) {  // changes contoured at once, taking the deferred tiles they reach
            groove_cut(model, 2 + step / 8);
            groove_cut(model, step / 8, 1);
            deferral.take_dirty(model);
            contourer.update(model);
        }
        check();
    }
    deferral.contour_all(model, contourer);
    if (refiner) refiner->finish(model, contourer);
    check();
    if (startup) {
        EXPECT_GT(cache.tiles().size(), first) << "the refinement's tiles arrived";
        // The refiner dropped once every tile is in, as the sculpt thread does: another view, read whole once.
        refiner.reset();
        check();
        EXPECT_EQ(cache.last_refresh_visits(), contourer.tile_count());
        visits -= contourer.tile_count();
        groove_cut(model, 1, 1);
        deferral.take_dirty(model);
        contourer.update(model);
        check();
        EXPECT_LT(cache.last_refresh_visits(), contourer.tile_count() / 4);
    }
    // The records answered: the refreshes after the first visited a small part of the tiles.
    EXPECT_LT(visits, (refreshes - 1) * contourer.tile_count() / 4) << visits << " visits in " << refreshes;
    EXPECT_GT(visits, 0u);
}

TEST(TileChangeLog, ACacheVisitingOnlyTheChangedTilesHoldsWhatAWholeScanReads) {
    {
        SCOPED_TRACE("during a coarse-first start-up");
        run_session(true);
    }
    {
        SCOPED_TRACE("after start-up");
        run_session(false);
    }
}

// A source whose meshes can be made to carry one material too few: the levels built from them then throw.
class SpoiledTiles final : public TileMeshSource {
public:
    explicit SpoiledTiles(const Contourer& c) : base_(c) {}
    bool spoil = false;
    std::size_t tile_count() const override { return base_.tile_count(); }
    std::array<int, 3> tile_dims() const override { return base_.tile_dims(); }
    std::size_t tile_triangle_count(std::size_t t) const override { return base_.tile_triangle_count(t); }
    std::uint64_t tile_version(std::size_t t) const override { return base_.tile_version(t); }
    TriMesh tile_mesh(std::size_t t, std::vector<std::uint8_t>& materials, std::vector<Vec3>& normals) const override {
        TriMesh m = base_.tile_mesh(t, materials, normals);
        if (spoil && !materials.empty()) materials.pop_back();
        return m;
    }
    bool changed_since(std::uint64_t mark, std::vector<std::uint64_t>& out) const override {
        return base_.changed_since(mark, out);
    }
    std::uint64_t change_view() const override { return base_.change_view(); }

private:
    ContourerTiles base_;
};

// A refresh that throws after reading the changed tiles (their levels, built at once) keeps its last mark: the next
// refresh reads those tiles again.
TEST(TileChangeLog, ARefreshThatThrowsKeepsItsMark) {
    TriDexel model = off_centre_sphere();
    Contourer contourer(model);
    contourer.update(model);
    SpoiledTiles source(contourer);
    TileSurfaceCache cache;
    TileLodOptions lod;
    lod.cell_m = model.lattice.cell_m;
    cache.enable_lod(lod);  // no worker, not deferred: refresh() builds the levels
    cache.refresh(source);
    groove_cut(model, 0);
    contourer.update(model);
    source.spoil = true;
    EXPECT_THROW(cache.refresh(source), Error);
    source.spoil = false;
    cache.refresh(source);
    EXPECT_LT(cache.last_refresh_visits(), contourer.tile_count() / 4);
    TileSurfaceCache whole;
    whole.refresh(contourer);
    expect_same_tiles(cache, whole);
}

TEST(TileChangeLog, AMarkFromBeforeTheRecordsGetsNoAnswer) {
    TriDexel model = off_centre_sphere();
    const std::uint64_t before = fresh_tile_version();
    Contourer contourer(model);
    StartupRefiner refiner(model, 1, model.lattice.to_world(Vec3(0.0)));
    DeferredContour deferral(model.tiles.tiles);
    const StartupRefiner::Source startup(contourer, refiner);
    const DeferredContour::Source source(startup, deferral);
    std::vector<std::uint64_t> out;
    EXPECT_FALSE(source.changed_since(before, out));
    EXPECT_TRUE(source.changed_since(fresh_tile_version(), out));
    EXPECT_TRUE(out.empty());
    EXPECT_NE(source.change_view(), 0u);
    EXPECT_NE(source.change_view(), DeferredContour::Source(ContourerTiles(contourer), deferral).change_view());
    EXPECT_EQ(TileSurfaceCache().last_refresh_visits(), 0u);
}

}  // namespace
}  // namespace tridex::compute
