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
    EXPECT_EQ(view.tiles[0].version, 0u) << "the changed tile was not taken in place";
    expect_links(view, p);
    // Without levels the groups go, though the objects are the same.
    tile_view_of(p.tiles, p.groups, false, view);
    EXPECT_TRUE(view.groups.empty());
    EXPECT_TRUE(view.tiles[3].levels.empty());
}

// Expects `a` and `b` to hold the same lists entry by entry (the levels by content, not by where they are stored).
void expect_same_view(const TileView& a, const TileView& b) {
    const auto same_levels = [](std::span<const renderer::TileMeshLevel> x,
                                std::span<const renderer::TileMeshLevel> y) {
        if (x.size() != y.size()) return false;
        for (std::size_t k = 0; k < x.size(); ++k)
            if (x[k].mesh != y[k].mesh || x[k].materials != y[k].materials || x[k].normals != y[k].normals ||
                x[k].error_m != y[k].error_m || x[k].own_triangles != y[k].own_triangles || x[k].joins != y[k].joins)
                return false;
        return true;
    };
    ASSERT_EQ(a.tiles.size(), b.tiles.size());
    ASSERT_EQ(a.groups.size(), b.groups.size());
    for (std::size_t i = 0; i < a.tiles.size(); ++i) {
        const renderer::TileMesh &x = a.tiles[i], &y = b.tiles[i];
        EXPECT_TRUE(x.mesh == y.mesh && x.version == y.version && x.id == y.id && x.materials == y.materials &&
                    x.normals == y.normals && x.group == y.group && x.bounds_m.lo == y.bounds_m.lo &&
                    x.bounds_m.hi == y.bounds_m.hi)
            << "tile " << i;
        EXPECT_TRUE(same_levels(x.levels, y.levels)) << "tile " << i;
    }
    for (std::size_t g = 0; g < a.groups.size(); ++g) {
        const renderer::TileGroup &x = a.groups[g], &y = b.groups[g];
        EXPECT_TRUE(x.id == y.id && x.version == y.version && x.parent == y.parent &&
                    x.children_cover == y.children_cover && x.levels_waiting == y.levels_waiting &&
                    x.neighbours == y.neighbours && x.bounds_m.lo == y.bounds_m.lo && x.bounds_m.hi == y.bounds_m.hi)
            << "group " << g;
        EXPECT_TRUE(same_levels(x.levels, y.levels)) << "group " << g;
    }
}

// Later publishes, as a sculpt thread makes them: some tiles and groups replaced by new objects of the same ids
// (other levels, more, fewer or none; versions; flags; a depth-1 group's children), some gone and some back. Each is
// merged into the lists by id (an unchanged tile keeps its entry) and equals a fresh fill of that publish.
TEST(TileView, LaterPublishesAreMergedByIdAsAFreshFillGivesThem) {
    for (const bool coarse : {false, true}) {
        SCOPED_TRACE(coarse ? "coarse group levels" : "simplified levels");
        Published all = publish(coarse ? 96 : 64, coarse);  // every object a round may list, sorted by id
        std::vector<bool> tile_in(all.tiles.size(), true), group_in(all.groups.size(), true);
        const auto listed = [&] {
            Published p;
            for (std::size_t i = 0; i < all.tiles.size(); ++i)
                if (tile_in[i]) p.tiles.push_back(all.tiles[i]);
            for (std::size_t g = 0; g < all.groups.size(); ++g)
                if (group_in[g]) p.groups.push_back(all.groups[g]);
            return p;
        };
        Published p = listed();
        TileView view;
        tile_view_of(p.tiles, p.groups, true, view);
        std::mt19937 rng(coarse ? 5 : 3);
        int merged = 0;
        std::vector<std::pair<std::size_t, std::shared_ptr<const compute::TileGroupSurface>>> fewer;  // as they were
        std::size_t joined = 0;
        while (joined < all.groups.size() &&
               std::none_of(all.groups[joined]->lods.begin(), all.groups[joined]->lods.end(),
                            [](const compute::TileLodLevel& l) { return l.joins != 0; }))
            ++joined;
        if (coarse) {
            ASSERT_LT(joined, all.groups.size()) << "no coarse level joins a neighbour";
        }
        TileView plain;  // the same publishes without levels
        tile_view_of(p.tiles, p.groups, false, plain);
        std::vector<std::size_t> gone_tiles, gone_groups;  // the last odd round's
        for (int round = 0; round < 8; ++round) {
            SCOPED_TRACE(round);
            std::size_t need = 0;          // the most levels this round can add after view.levels' end
            for (int k = 0; k < 6; ++k) {  // tiles: a new version, their levels cut to one or dropped, or doubled
                const std::size_t i = rng() % all.tiles.size();
                auto t = std::make_shared<compute::TileSurface>(*all.tiles[i]);
                t->version += 1000;
                if (k % 3 == 0 && t->lods.size() > 1) t->lods.resize(1);
                if (k % 3 == 1) t->lods.clear();
                if (k % 3 == 2) t->lods.insert(t->lods.end(), t->lods.begin(), t->lods.end());
                need += t->lods.size();
                all.tiles[i] = t;
            }
            for (int k = 0; k < 6; ++k) {  // groups: a new version and flags, a level more or less
                const std::size_t g = rng() % all.groups.size();
                auto s = std::make_shared<compute::TileGroupSurface>(*all.groups[g]);
                s->version += 1000;
                s->children_cover = !s->children_cover;
                s->levels_waiting = !s->levels_waiting;
                if (k % 2 == 0 && !s->lods.empty()) s->lods.push_back(s->lods.back());
                if (k % 2 == 1 && s->lods.size() > 1) s->lods.pop_back();
                s->bounds_m = s->bounds_m.inflated(0.001);
                need += s->lods.size();
                all.groups[g] = s;
            }
            // Odd rounds only: tiles and groups gone or back, and a depth-1 group's children (even rounds keep every
            // group in its place, so that carried entries keep their indices).
            // The last odd round's gone ones come back.
            for (int k = 0; k < (round % 2 == 1 ? 4 : 0); ++k) {
                const std::size_t i = rng() % all.tiles.size(), g = rng() % all.groups.size();
                tile_in[i] = !tile_in[i];
                group_in[g] = !group_in[g];
                need += all.tiles[i]->lods.size() + all.groups[g]->lods.size();
                gone_tiles.push_back(i);
                gone_groups.push_back(g);
            }
            for (std::size_t n = 0; round % 2 == 1 && n + 4 < gone_tiles.size(); ++n) {
                tile_in[gone_tiles[n]] = !tile_in[gone_tiles[n]];
                group_in[gone_groups[n]] = !group_in[gone_groups[n]];
                need += all.tiles[gone_tiles[n]]->lods.size() + all.groups[gone_groups[n]]->lods.size();
            }
            if (round % 2 == 1 && gone_tiles.size() > 4) {
                gone_tiles.erase(gone_tiles.begin(), gone_tiles.end() - 4);
                gone_groups.erase(gone_groups.begin(), gone_groups.end() - 4);
            }
            // A depth-1 group lists one child fewer; the last odd round's lists it again.
            for (std::size_t n = 0; round % 2 == 1 && n < fewer.size(); ++n) {
                all.groups[fewer[n].first] = fewer[n].second;
                need += fewer[n].second->lods.size();
            }
            if (round % 2 == 1) fewer.clear();
            for (std::size_t g = rng() % all.groups.size(); round % 2 == 1 && g < all.groups.size(); ++g)
                if (all.groups[g]->depth == 1 && all.groups[g]->children.size() > 1) {
                    fewer.emplace_back(g, all.groups[g]);
                    auto s = std::make_shared<compute::TileGroupSurface>(*all.groups[g]);
                    s->children.erase(s->children.begin() + static_cast<std::ptrdiff_t>(rng() % s->children.size()));
                    need += s->lods.size();
                    all.groups[g] = s;
                    break;
                }
            // A group whose levels join neighbours goes in round 1 and comes back in round 3.
            if (joined < all.groups.size() && (round == 1 || round == 3)) {
                group_in[joined] = round == 3;
                need += all.groups[joined]->lods.size();
            }
            const Published last = p;
            p = listed();
            // A tile both publishes list as the same object, marked in the view: a merge carries its entry.
            std::size_t mark = 0;
            while (mark < last.tiles.size() &&
                   std::find(p.tiles.begin(), p.tiles.end(), last.tiles[mark]) == p.tiles.end())
                ++mark;
            ASSERT_LT(mark, last.tiles.size());
            const std::uint64_t marked_id = last.tiles[mark]->id;
            view.tiles[mark].version = 0;
            plain.tiles[mark].version = 0;
            const bool room = view.levels.capacity() - view.levels.size() >= need;
            tile_view_of(p.tiles, p.groups, true, view);
            tile_view_of(p.tiles, p.groups, false, plain);
            TileView plain_fresh;
            tile_view_of(p.tiles, p.groups, false, plain_fresh);
            const auto plain_at = std::find_if(plain.tiles.begin(), plain.tiles.end(),
                                               [&](const renderer::TileMesh& t) { return t.id == marked_id; });
            ASSERT_NE(plain_at, plain.tiles.end());
            EXPECT_EQ(plain_at->version, 0u) << "the lists without levels were filled anew";
            plain_at->version = plain_fresh.tiles[static_cast<std::size_t>(plain_at - plain.tiles.begin())].version;
            expect_same_view(plain, plain_fresh);
            EXPECT_TRUE(plain.groups.empty());
            const auto at = std::find_if(view.tiles.begin(), view.tiles.end(),
                                         [&](const renderer::TileMesh& t) { return t.id == marked_id; });
            ASSERT_NE(at, view.tiles.end());
            if (room) {
                EXPECT_EQ(at->version, 0u) << "the lists were filled anew though the levels had room";
                ++merged;
            }
            at->version = (*std::find_if(p.tiles.begin(), p.tiles.end(), [&](const auto& t) {
                              return t->id == marked_id;
                          }))->version;
            TileView fresh;
            tile_view_of(p.tiles, p.groups, true, fresh);
            expect_same_view(view, fresh);
            if (coarse) {
                EXPECT_GT(expect_neighbours(view, p), 0u);
            }
        }
        EXPECT_GE(merged, 4) << "too few rounds had room for a merge";
        // Lists with a null entry, or out of id order, are filled anew (a null entry is skipped).
        for (const bool reversed : {false, true}) {
            Published odd = p;
            if (reversed)
                std::reverse(odd.tiles.begin(), odd.tiles.end());
            else
                odd.tiles[1] = nullptr;
            tile_view_of(odd.tiles, odd.groups, true, view);
            TileView fresh;
            tile_view_of(odd.tiles, odd.groups, true, fresh);
            expect_same_view(view, fresh);
            EXPECT_EQ(view.tiles.size(), p.tiles.size() - (reversed ? 0 : 1));
        }
    }
}

}  // namespace
}  // namespace tridex::app
