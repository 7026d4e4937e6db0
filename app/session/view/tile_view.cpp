// app/session/view/tile_view.cpp - TileSurface / TileGroupSurface -> renderer::TileMesh / TileGroup.
#include "app/session/view/tile_view.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <iterator>
#include <utility>

#include "compute/contour/lod_worker.hpp"
#include "core/error.hpp"

namespace tridex::app {
namespace {

renderer::TileMeshLevel level_of(const compute::TileLodLevel& l) {
    return renderer::TileMeshLevel{&l.mesh, l.materials.empty() ? nullptr : &l.materials, &l.normals, l.error_m,
                                   l.own_triangles, l.joins};
}

// (id, index) pairs sorted by id, and the index of `id` among them (`none` when absent).
using IdIndex = std::vector<std::pair<std::uint64_t, std::size_t>>;
using TileGroupPair = std::pair<std::uint64_t, std::uint64_t>;  // (tile id, id of its depth-1 group)
std::size_t find_index(const IdIndex& sorted, std::uint64_t id, std::size_t none) {
    const auto it = std::lower_bound(sorted.begin(), sorted.end(), std::pair<std::uint64_t, std::size_t>{id, 0});
    return it != sorted.end() && it->first == id ? it->second : none;
}

// A group's depth and coordinates as one sortable key (coordinates are below 2^16 tiles).
std::uint64_t place_key(int depth, const std::array<int, 3>& c) {
    return (static_cast<std::uint64_t>(depth) << 48) | (static_cast<std::uint64_t>(c[2] & 0xffff) << 32) |
           (static_cast<std::uint64_t>(c[1] & 0xffff) << 16) | static_cast<std::uint64_t>(c[0] & 0xffff);
}

// Every level's `joins`, or-ed.
std::uint32_t joins_of(const compute::TileGroupSurface& s) {
    std::uint32_t joins = 0;
    for (const compute::TileLodLevel& l : s.lods) joins |= l.joins;
    return joins;
}

// A group's entry with its own fields (no levels, parent or neighbours).
renderer::TileGroup group_entry(const compute::TileGroupSurface& s) {
    renderer::TileGroup tg;
    tg.id = s.id;
    tg.bounds_m = s.bounds_m;
    tg.version = s.version;
    tg.children_cover = s.children_cover;
    tg.levels_waiting = s.levels_waiting;
    return tg;
}

// A tile's entry with its own fields (no levels or group).
renderer::TileMesh tile_entry(const compute::TileSurface& s) {
    renderer::TileMesh tm;
    tm.mesh = &s.mesh;
    tm.bounds_m = s.bounds_m;
    tm.version = s.version;
    tm.id = s.id;
    tm.materials = &s.materials;
    tm.normals = &s.normals;
    return tm;
}

// Calls f(slot, coords) for each place around group `s` at its depth (compute::neighbour_bit's slots, the group's
// own slot 13 included) whose coordinates are not negative.
template <typename F>
void for_each_place_around(const compute::TileGroupSurface& s, F&& f) {
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const std::array<int, 3> c{s.coords[0] + dx, s.coords[1] + dy, s.coords[2] + dz};
                if (c[0] >= 0 && c[1] >= 0 && c[2] >= 0) f(compute::neighbour_bit(dx, dy, dz), c);
            }
}

// The slot that names a group from the neighbour in `slot`: the opposite offset.
int opposite_slot(int slot) { return 26 - slot; }

// Sets tg.neighbours for group `s`: the index of the group of the same depth in each slot its levels join, from
// `by_place` (place_key -> index in the groups' list, sorted); kNone in every other slot.
void link_group(const compute::TileGroupSurface& s, const IdIndex& by_place, renderer::TileGroup& tg) {
    tg.neighbours = renderer::TileGroup::no_neighbours();
    const std::uint32_t joins = joins_of(s);
    if (joins == 0) return;
    for_each_place_around(s, [&](int slot, const std::array<int, 3>& c) {
        if (joins & (1u << slot))
            tg.neighbours[static_cast<std::size_t>(slot)] =
                find_index(by_place, place_key(s.depth, c), renderer::TileGroup::kNone);
    });
}

// Points `at` at `lods` as levels: in place of the span it held where they fit, else after out.levels' end. Returns
// false, changing nothing, when that end has no room left within out.levels' capacity (a reallocation would move
// every other entry's levels).
bool put_levels(const std::vector<compute::TileLodLevel>& lods, std::span<const renderer::TileMeshLevel>& at,
                TileView& out) {
    if (lods.empty()) {
        at = {};
        return true;
    }
    renderer::TileMeshLevel* first = nullptr;
    if (lods.size() <= at.size()) {
        first = out.levels.data() + (at.data() - out.levels.data());
        for (std::size_t k = 0; k < lods.size(); ++k) first[k] = level_of(lods[k]);
    } else {
        if (out.levels.size() + lods.size() > out.levels.capacity()) return false;
        const std::size_t begin = out.levels.size();
        for (const compute::TileLodLevel& l : lods) out.levels.push_back(level_of(l));
        first = out.levels.data() + begin;
    }
    at = std::span<const renderer::TileMeshLevel>(first, lods.size());
    return true;
}

// TileGroup::neighbours of the groups whose levels join neighbours (the coarse levels with own triangles), and
// out.group_places. out.groups holds the non-null groups in order.
template <typename GetGroup>
void link_neighbours(std::size_t group_count, GetGroup&& get_group, TileView& out) {
    IdIndex& by_place = out.group_places;
    by_place.clear();
    for (std::size_t g = 0; g < group_count; ++g)
        if (const compute::TileGroupSurface* s = get_group(g))
            by_place.emplace_back(place_key(s->depth, s->coords), by_place.size());
    std::sort(by_place.begin(), by_place.end());
    std::size_t at = 0;  // index in out.groups
    for (std::size_t g = 0; g < group_count; ++g)
        if (const compute::TileGroupSurface* s = get_group(g)) link_group(*s, by_place, out.groups[at++]);
}

template <typename GetTile, typename GetGroup>
void fill(std::size_t count, GetTile&& get, std::size_t group_count, GetGroup&& get_group, bool with_lods,
          TileView& out) {
    out.tiles.clear();
    out.groups.clear();
    out.levels.clear();
    if (!with_lods) group_count = 0;
    std::size_t level_count = 0;
    for (std::size_t i = 0; i < count; ++i)
        if (const compute::TileSurface* s = get(i); s && with_lods) level_count += s->lods.size();
    for (std::size_t g = 0; g < group_count; ++g)
        if (const compute::TileGroupSurface* s = get_group(g)) level_count += s->lods.size();
    // The spans below point into it: no reallocation after this. The slack takes the levels of tiles and groups that
    // later publishes add or replace with more levels than they had (merge_update).
    out.levels.reserve(level_count + level_count / 2 + 64);
    IdIndex group_index;              // group id -> index in out.groups, sorted by id
    group_index.reserve(group_count);
    for (std::size_t g = 0; g < group_count; ++g)
        if (const compute::TileGroupSurface* s = get_group(g)) {
            group_index.emplace_back(s->id, out.groups.size());
            renderer::TileGroup tg = group_entry(*s);
            put_levels(s->lods, tg.levels, out);  // within the room reserved above
            out.groups.push_back(tg);
        }
    std::sort(group_index.begin(), group_index.end());  // for the lookups below
    IdIndex tile_group;  // tile id -> index of its depth-1 group, sorted by tile id
    for (std::size_t g = 0; g < group_count; ++g)
        if (const compute::TileGroupSurface* s = get_group(g)) {
            const std::size_t at = find_index(group_index, s->id, renderer::TileGroup::kNone);
            out.groups[at].parent = find_index(group_index, s->parent, renderer::TileGroup::kNone);
            if (s->depth == 1)
                for (const std::uint64_t t : s->children) tile_group.emplace_back(t, at);
        }
    std::sort(tile_group.begin(), tile_group.end());
    out.tile_groups.clear();
    out.tile_groups.reserve(tile_group.size());
    for (const auto& [tile, at] : tile_group) out.tile_groups.emplace_back(tile, out.groups[at].id);
    link_neighbours(group_count, get_group, out);
    out.tiles.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        const compute::TileSurface* s = get(i);
        if (!s) continue;
        renderer::TileMesh tm = tile_entry(*s);
        if (with_lods) put_levels(s->lods, tm.levels, out);  // within the room reserved above
        tm.group = find_index(tile_group, s->id, renderer::TileMesh::kNoGroup);
        out.tiles.push_back(tm);
    }
}

// True when every item is set and the ids ascend strictly.
template <typename T>
bool sorted_by_id(std::span<const std::shared_ptr<const T>> items) {
    for (std::size_t i = 0; i < items.size(); ++i)
        if (!items[i] || (i > 0 && items[i - 1]->id >= items[i]->id)) return false;
    return true;
}

// The index of the group with id `id` in `groups` (ascending ids), or kNone.
std::size_t group_at(const std::vector<renderer::TileGroup>& groups, std::uint64_t id) {
    const auto it = std::lower_bound(groups.begin(), groups.end(), id,
                                     [](const renderer::TileGroup& g, std::uint64_t v) { return g.id < v; });
    return it != groups.end() && it->id == id ? static_cast<std::size_t>(it - groups.begin())
                                              : renderer::TileGroup::kNone;
}

// out.tile_groups without the pairs of `gone` and with those of `came` (both sorted here).
void move_tile_groups(std::vector<TileGroupPair>& gone, std::vector<TileGroupPair>& came, TileView& out) {
    std::sort(gone.begin(), gone.end());
    std::sort(came.begin(), came.end());
    std::vector<TileGroupPair> kept;
    kept.reserve(out.tile_groups.size() + came.size());
    std::set_difference(out.tile_groups.begin(), out.tile_groups.end(), gone.begin(), gone.end(),
                        std::back_inserter(kept));
    out.tile_groups.clear();
    std::merge(kept.begin(), kept.end(), came.begin(), came.end(), std::back_inserter(out.tile_groups));
}

// The group list of the merge below: out.groups' entries carried to their new places (the same objects as is, a
// replaced object rewritten over its old levels), new groups added, gone ones dropped. remap: old index -> new index
// or kNone. Tiles that change group go to `gone` / `came`. Returns false when the levels have no room.
bool merge_groups(std::span<const std::shared_ptr<const compute::TileGroupSurface>> groups, TileView& out,
                  std::vector<std::size_t>& remap, std::vector<TileGroupPair>& gone, std::vector<TileGroupPair>& came,
                  std::vector<std::size_t>& relink, std::vector<std::size_t>& added) {
    constexpr std::size_t kNone = renderer::TileGroup::kNone;
    const std::vector<std::shared_ptr<const compute::TileGroupSurface>>& old = out.from_groups;
    std::vector<renderer::TileGroup>& next = out.spare_groups;
    next.clear();
    next.reserve(groups.size());
    remap.assign(old.size(), kNone);
    const auto leave = [&](const compute::TileGroupSurface& g) {
        if (g.depth == 1)
            for (const std::uint64_t t : g.children) gone.emplace_back(t, g.id);
    };
    const auto join = [&](const compute::TileGroupSurface& g) {
        if (g.depth == 1)
            for (const std::uint64_t t : g.children) came.emplace_back(t, g.id);
    };
    std::size_t i = 0;
    for (std::size_t j = 0; j < groups.size(); ++j) {
        const std::shared_ptr<const compute::TileGroupSurface>& now = groups[j];
        if (!now) return false;
        // The id from the entry where the object is the one it was made from: the objects are not read.
        const std::uint64_t id = i < old.size() && old[i] == now ? out.groups[i].id : now->id;
        if (!next.empty() && id <= next.back().id) return false;  // not sorted by id
        for (; i < old.size() && out.groups[i].id < id; ++i) leave(*old[i]);
        if (i < old.size() && out.groups[i].id == id) {
            renderer::TileGroup tg = out.groups[i];
            if (old[i] != now) {
                // An id names one place and parent; a list where it does not is filled anew.
                if (now->parent != old[i]->parent || now->depth != old[i]->depth || now->coords != old[i]->coords)
                    return false;
                const renderer::TileGroup was = tg;
                tg = group_entry(*now);
                tg.levels = was.levels;
                tg.parent = was.parent;  // the same id's parent: mapped through remap below if groups moved
                if (!put_levels(now->lods, tg.levels, out)) return false;
                relink.push_back(j);
                if (now->children != old[i]->children) {
                    leave(*old[i]);
                    join(*now);
                }
            }
            remap[i++] = j;
            next.push_back(tg);
        } else {
            renderer::TileGroup tg = group_entry(*now);
            if (!put_levels(now->lods, tg.levels, out)) return false;
            relink.push_back(j);
            added.push_back(j);
            join(*now);
            next.push_back(tg);
        }
    }
    for (; i < old.size(); ++i) leave(*old[i]);
    return true;
}

// Parents, group_places and neighbours of the merged groups (`next`, for `groups`): carried entries map their indices
// through `remap`; rewritten and new ones are linked again, and a new group is linked into the neighbours that join it.
void link_merged(std::span<const std::shared_ptr<const compute::TileGroupSurface>> groups,
                 const std::vector<std::size_t>& remap, const std::vector<std::size_t>& relink,
                 const std::vector<std::size_t>& added, TileView& out) {
    constexpr std::size_t kNone = renderer::TileGroup::kNone;
    std::vector<renderer::TileGroup>& next = out.spare_groups;
    const bool moved = !added.empty() || next.size() != remap.size() ||
                       std::any_of(remap.begin(), remap.end(), [](std::size_t r) { return r == kNone; });
    if (moved) {
        // Carried and rewritten entries map their old indices; a group whose parent is not listed (or a new one) looks
        // for it, since it may have come.
        for (std::size_t j = 0; j < next.size(); ++j) {
            std::size_t& parent = next[j].parent;
            if (parent != kNone) parent = remap[parent];
            if (parent == kNone && !added.empty()) parent = group_at(next, groups[j]->parent);
            for (std::size_t& n : next[j].neighbours)
                if (n != kNone) n = remap[n];
        }
        IdIndex places;  // the carried groups' places, still in order, then the new groups' merged in
        places.reserve(next.size());
        for (const auto& [key, at] : out.group_places)
            if (remap[at] != kNone) places.emplace_back(key, remap[at]);
        IdIndex came;
        for (const std::size_t a : added) came.emplace_back(place_key(groups[a]->depth, groups[a]->coords), a);
        std::sort(came.begin(), came.end());
        out.group_places.clear();
        std::merge(places.begin(), places.end(), came.begin(), came.end(), std::back_inserter(out.group_places));
    }
    for (const std::size_t j : relink) link_group(*groups[j], out.group_places, next[j]);
    for (const std::size_t a : added)
        for_each_place_around(*groups[a], [&](int slot, const std::array<int, 3>& c) {
            const std::size_t n = find_index(out.group_places, place_key(groups[a]->depth, c), kNone);
            const int back = opposite_slot(slot);  // the slot that names `a` from n
            if (n != kNone && n != a && (joins_of(*groups[n]) & (1u << back)))
                next[n].neighbours[static_cast<std::size_t>(back)] = a;
        });
}

// The lists `out` was filled from (tile_view_of's shared overload, ids ascending, no null entry) brought to `surfaces`
// and `groups` (the same) by one merge by id: an entry whose object is the same is carried as it is, a replaced one
// rewritten (over its old levels where they fit), new ones added and gone ones dropped; parents, neighbours and the
// tiles' groups follow (out.tile_groups). O(tiles + groups), plus a search per new or moved entry; an unchanged object
// is not read to find its place (its id is its entry's). Returns false when the lists are not sorted, hold a null
// entry, or give an id another place or parent, or when the levels have no room left (out.levels then holds unused
// levels): fill() then makes the lists anew.
bool merge_update(std::span<const std::shared_ptr<const compute::TileSurface>> surfaces,
                  std::span<const std::shared_ptr<const compute::TileGroupSurface>> groups, bool with_lods,
                  TileView& out) {
    if (!out.from_shared || !out.from_sorted || out.from_lods != with_lods) return false;
    // Until the merge is done the lists match no publish: an exception on the way leaves them to a fill.
    out.from_shared = false;
    std::vector<std::size_t> remap, relink, added;
    std::vector<TileGroupPair> gone, came;
    if (with_lods) {
        if (!merge_groups(groups, out, remap, gone, came, relink, added)) return false;
        link_merged(groups, remap, relink, added, out);
        if (!gone.empty() || !came.empty()) move_tile_groups(gone, came, out);
    }
    const std::vector<std::shared_ptr<const compute::TileSurface>>& old = out.from_tiles;
    const std::vector<renderer::TileGroup>& next_groups = out.spare_groups;
    std::vector<renderer::TileMesh>& next = out.spare_tiles;
    next.clear();
    next.reserve(surfaces.size());
    std::size_t i = 0, k = 0;  // in old / out.tile_groups
    for (std::size_t j = 0; j < surfaces.size(); ++j) {
        const std::shared_ptr<const compute::TileSurface>& now = surfaces[j];
        if (!now) return false;
        const std::uint64_t id = i < old.size() && old[i] == now ? out.tiles[i].id : now->id;
        if (!next.empty() && id <= next.back().id) return false;  // not sorted by id
        while (i < old.size() && out.tiles[i].id < id) ++i;
        const bool kept = i < old.size() && out.tiles[i].id == id;
        renderer::TileMesh tm;
        if (kept && old[i] == now) {
            tm = out.tiles[i];
        } else {
            tm = tile_entry(*now);
            if (kept) tm.levels = out.tiles[i].levels;
            if (!with_lods)
                tm.levels = {};
            else if (!put_levels(now->lods, tm.levels, out))
                return false;
        }
        tm.group = renderer::TileMesh::kNoGroup;
        if (with_lods) {
            while (k < out.tile_groups.size() && out.tile_groups[k].first < id) ++k;
            if (k < out.tile_groups.size() && out.tile_groups[k].first == id) {
                const std::uint64_t gid = out.tile_groups[k].second;
                const std::size_t was = kept ? out.tiles[i].group : renderer::TileMesh::kNoGroup;
                const std::size_t g = was < remap.size() ? remap[was] : renderer::TileGroup::kNone;
                tm.group = g != renderer::TileGroup::kNone && next_groups[g].id == gid ? g : group_at(next_groups, gid);
            }
        }
        next.push_back(tm);
    }
    out.tiles.swap(next);
    if (with_lods) out.groups.swap(out.spare_groups);
    out.from_tiles.assign(surfaces.begin(), surfaces.end());
    out.from_groups.assign(groups.begin(), groups.end());
    out.from_shared = true;
    return true;
}

}  // namespace

void tile_view_of(std::span<const std::shared_ptr<const compute::TileSurface>> surfaces,
                  std::span<const std::shared_ptr<const compute::TileGroupSurface>> groups, bool with_lods,
                  TileView& out) {
    // A published tile or group is never changed, and `out` holds the ones it was filled from: the same objects
    // give the same lists.
    if (out.from_shared && out.from_lods == with_lods &&
        std::equal(surfaces.begin(), surfaces.end(), out.from_tiles.begin(), out.from_tiles.end()) &&
        std::equal(groups.begin(), groups.end(), out.from_groups.begin(), out.from_groups.end()))
        return;
    if (merge_update(surfaces, groups, with_lods, out)) return;
    out.from_tiles.assign(surfaces.begin(), surfaces.end());
    out.from_groups.assign(groups.begin(), groups.end());
    out.from_lods = with_lods;
    out.from_shared = true;
    out.from_sorted = sorted_by_id(surfaces) && sorted_by_id(groups);
    fill(surfaces.size(), [&](std::size_t i) { return surfaces[i].get(); }, groups.size(),
         [&](std::size_t g) { return groups[g].get(); }, with_lods, out);
}

void tile_view_of(std::span<const compute::TileSurface> surfaces, std::span<const compute::TileGroupSurface> groups,
                  bool with_lods, TileView& out) {
    out.from_tiles.clear();  // these lists change in place: nothing to recognise them by
    out.from_groups.clear();
    out.from_shared = false;
    out.from_sorted = false;
    fill(surfaces.size(), [&](std::size_t i) { return &surfaces[i]; }, groups.size(),
         [&](std::size_t g) { return &groups[g]; }, with_lods, out);
}

LodChoice lod_choice(const std::string& name) {
    if (name == "off") return LodChoice{false, 0};
    if (name == "on") return LodChoice{true, compute::kCoarseGroupsFromCells};
    if (name == "coarse") return LodChoice{true, 1};
    if (name == "simplified") return LodChoice{true, 0};
    throw Error("must be on, off, coarse or simplified, got \"" + name + "\"");
}

}  // namespace tridex::app
