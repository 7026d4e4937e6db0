// tests/app/test_tile_view.cpp - the renderer's view of published tiles and groups (app/session/view/tile_view.hpp):
// each group's parent, each tile's depth-1 group and the neighbours a coarse level joins as their ids say, whatever
// the lists' order, and a frame given the same published objects again keeps its lists while a changed tile is
// taken in.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include "app/scene/workpiece_source.hpp"
#include "app/support/assets.hpp"
#include "app/session/view/tile_view.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"

namespace tridex::app {
namespace {

struct Published {
    std::vector<std::shared_ptr<const compute::TileSurface>> tiles;
    std::vector<std::shared_ptr<const compute::TileGroupSurface>> groups;
};

// The bunny at `cells` cells, contoured in tiles as a sculpt thread publishes it: with simplified group levels of
// depths 1-2, or with coarse group levels (contoured from the model read at strides 2, 4 and 8), settled.
Published publish(int cells = 64, bool coarse = false) {
    Workpiece wp = prepare_workpiece(default_mesh_path(), cells, 0.3, Vec3(0.0, 0.0, 0.3));
    compute::Contourer contourer(wp.model);
    contourer.update(wp.model);
    compute::TileSurfaceCache cache;
    compute::TileLodOptions o;
    o.cell_m = wp.model.lattice.cell_m;
    if (!coarse) o.group_depth = 2;
    cache.enable_lod(o);
    if (coarse) cache.use_coarse_groups(wp.model);
    cache.refresh(contourer);
    while (cache.coarse_waiting() > 0) EXPECT_GT(cache.collect_lods(), 0u);
    Published p;
    for (const compute::TileSurface& t : cache.tiles()) p.tiles.push_back(std::make_shared<compute::TileSurface>(t));
    for (const compute::TileGroupSurface& g : cache.groups())
        p.groups.push_back(std::make_shared<compute::TileGroupSurface>(g));
    return p;
}

// Checks the neighbours of `view`'s groups against `p`: each slot a level joins names the group of the same depth at
// that offset, or none where there is none. Returns the slots checked that name a group.
std::size_t expect_neighbours(const TileView& view, const Published& p) {
    std::map<std::uint64_t, const compute::TileGroupSurface*> by_id;
    std::map<std::pair<int, std::array<int, 3>>, std::uint64_t> by_place;
    for (const auto& g : p.groups) {
        by_id[g->id] = g.get();
        by_place[{g->depth, g->coords}] = g->id;
    }
    std::size_t named = 0;
    for (const renderer::TileGroup& g : view.groups) {
        const compute::TileGroupSurface* s = by_id.at(g.id);
        std::uint32_t joins = 0;
        for (std::size_t k = 0; k < s->lods.size(); ++k) {
            EXPECT_EQ(g.levels[k].own_triangles, s->lods[k].own_triangles);
            EXPECT_EQ(g.levels[k].joins, s->lods[k].joins);
            joins |= s->lods[k].joins;
        }
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int slot = compute::neighbour_bit(dx, dy, dz);
                    if (!(joins & (1u << slot))) continue;
                    const auto it = by_place.find({s->depth, {s->coords[0] + dx, s->coords[1] + dy, s->coords[2] + dz}});
                    const std::size_t nb = g.neighbours[static_cast<std::size_t>(slot)];
                    if (it == by_place.end()) {
                        EXPECT_EQ(nb, renderer::TileGroup::kNone) << g.id << " slot " << slot;
                        continue;
                    }
                    ++named;
                    EXPECT_LT(nb, view.groups.size()) << g.id << " slot " << slot;
                    if (nb < view.groups.size()) {
                        EXPECT_EQ(view.groups[nb].id, it->second) << g.id << " slot " << slot;
                    }
                }
    }
    return named;
}

// Checks `view` against `p` through ids: every group's parent index names its parent's id, every tile's group index
// the depth-1 group that lists it.
void expect_links(const TileView& view, const Published& p) {
    std::map<std::uint64_t, const compute::TileGroupSurface*> by_id;
    std::map<std::uint64_t, std::uint64_t> tile_group;
    for (const auto& g : p.groups) {
        by_id[g->id] = g.get();
        if (g->depth == 1)
            for (const std::uint64_t t : g->children) tile_group[t] = g->id;
    }
    ASSERT_EQ(view.groups.size(), p.groups.size());
    ASSERT_EQ(view.tiles.size(), p.tiles.size());
    std::size_t parents = 0, grouped = 0;
    for (const renderer::TileGroup& g : view.groups) {
        const compute::TileGroupSurface* s = by_id.at(g.id);
        if (by_id.contains(s->parent)) {
            ASSERT_LT(g.parent, view.groups.size()) << g.id;
            EXPECT_EQ(view.groups[g.parent].id, s->parent) << g.id;
            ++parents;
        } else {
            EXPECT_EQ(g.parent, renderer::TileGroup::kNone) << g.id;
        }
        EXPECT_EQ(g.levels.size(), s->lods.size()) << g.id;
    }
    for (const renderer::TileMesh& t : view.tiles) {
        if (tile_group.contains(t.id)) {
            ASSERT_LT(t.group, view.groups.size()) << t.id;
            EXPECT_EQ(view.groups[t.group].id, tile_group.at(t.id)) << t.id;
            ++grouped;
        } else {
            EXPECT_EQ(t.group, renderer::TileMesh::kNoGroup) << t.id;
        }
    }
    EXPECT_GT(parents, 0u);
    EXPECT_GT(grouped, 0u);
}

TEST(TileView, LinksFollowTheIdsInAnyOrder) {
    Published p = publish();
    ASSERT_FALSE(p.groups.empty());
    TileView view;
    tile_view_of(p.tiles, p.groups, true, view);
    expect_links(view, p);
    std::mt19937 rng(7);
    std::shuffle(p.tiles.begin(), p.tiles.end(), rng);
    std::shuffle(p.groups.begin(), p.groups.end(), rng);
    tile_view_of(p.tiles, p.groups, true, view);
    expect_links(view, p);
}

TEST(TileView, CoarseLevelsNameTheNeighboursTheyJoinInAnyOrder) {
    Published p = publish(96, true);
    TileView view;
    tile_view_of(p.tiles, p.groups, true, view);
    expect_links(view, p);
    EXPECT_GT(expect_neighbours(view, p), 0u);
    std::mt19937 rng(11);
    std::shuffle(p.groups.begin(), p.groups.end(), rng);
    tile_view_of(p.tiles, p.groups, true, view);
    EXPECT_GT(expect_neighbours(view, p), 0u);
}

TEST(TileView, TheSamePublishedObjectsKeepTheListsAndAChangedTileIsTakenIn) {
    Published p = publish();
    TileView view;
    tile_view_of(p.tiles, p.groups, true, view);
    const renderer::TileMesh* tiles = view.tiles.data();
    const renderer::TileMeshLevel* levels = view.levels.data();
    const std::size_t count = view.tiles.size();
    // A copy of the lists (another MeshFrame of the same publish): the same objects, the lists stay.
    const Published again = p;
    view.tiles[0].version = 0;  // a mark a refill would overwrite
    tile_view_of(again.tiles, again.groups, true, view);
    EXPECT_EQ(view.tiles.data(), tiles);
    EXPECT_EQ(view.levels.data(), levels);
    EXPECT_EQ(view.tiles[0].version, 0u) << "the lists were rebuilt";
    // A publish that re-contoured one tile: a new object with a new version.
    auto changed = std::make_shared<compute::TileSurface>(*p.tiles[3]);
    changed->version += 1000;
    p.tiles[3] = changed;
    tile_view_of(p.tiles, p.groups, true, view);
    ASSERT_EQ(view.tiles.size(), count);
    EXPECT_EQ(view.tiles[3].version, changed->version);
    EXPECT_EQ(view.tiles[3].mesh, &changed->mesh);
    EXPECT_NE(view.tiles[0].version, 0u);
    expect_links(view, p);
    // Without levels the groups go, though the objects are the same.
    tile_view_of(p.tiles, p.groups, false, view);
    EXPECT_TRUE(view.groups.empty());
    EXPECT_TRUE(view.tiles[3].levels.empty());
}

}  // namespace
}  // namespace tridex::app
