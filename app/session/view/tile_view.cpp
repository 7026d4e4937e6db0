// app/session/view/tile_view.cpp - TileSurface / TileGroupSurface -> renderer::TileMesh / TileGroup.
#include "app/session/view/tile_view.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
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
std::size_t find_index(const IdIndex& sorted, std::uint64_t id, std::size_t none) {
    const auto it = std::lower_bound(sorted.begin(), sorted.end(), std::pair<std::uint64_t, std::size_t>{id, 0});
    return it != sorted.end() && it->first == id ? it->second : none;
}

// A group's depth and coordinates as one sortable key (coordinates are below 2^16 tiles).
std::uint64_t place_key(int depth, const std::array<int, 3>& c) {
    return (static_cast<std::uint64_t>(depth) << 48) | (static_cast<std::uint64_t>(c[2] & 0xffff) << 32) |
           (static_cast<std::uint64_t>(c[1] & 0xffff) << 16) | static_cast<std::uint64_t>(c[0] & 0xffff);
}

// TileGroup::neighbours of the groups whose levels join neighbours (the coarse levels with own triangles).
// out.groups holds the non-null groups in order.
template <typename GetGroup>
void link_neighbours(std::size_t group_count, GetGroup&& get_group, TileView& out) {
    IdIndex by_place;  // place_key -> index in out.groups, sorted
    bool any = false;
    for (std::size_t g = 0; g < group_count; ++g)
        if (const compute::TileGroupSurface* s = get_group(g)) {
            by_place.emplace_back(place_key(s->depth, s->coords), by_place.size());
            for (const compute::TileLodLevel& l : s->lods) any = any || l.joins != 0;
        }
    if (!any) return;
    std::sort(by_place.begin(), by_place.end());
    std::size_t at = 0;  // index in out.groups
    for (std::size_t g = 0; g < group_count; ++g) {
        const compute::TileGroupSurface* s = get_group(g);
        if (!s) continue;
        renderer::TileGroup& tg = out.groups[at++];
        std::uint32_t joins = 0;
        for (const compute::TileLodLevel& l : s->lods) joins |= l.joins;
        if (joins == 0) continue;
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int slot = compute::neighbour_bit(dx, dy, dz);
                    const std::array<int, 3> c{s->coords[0] + dx, s->coords[1] + dy, s->coords[2] + dz};
                    if (!(joins & (1u << slot)) || c[0] < 0 || c[1] < 0 || c[2] < 0) continue;
                    tg.neighbours[static_cast<std::size_t>(slot)] =
                        find_index(by_place, place_key(s->depth, c), renderer::TileGroup::kNone);
                }
    }
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
    out.levels.reserve(level_count);  // the spans below point into it: no reallocation after this
    IdIndex group_index;              // group id -> index in out.groups, sorted by id
    group_index.reserve(group_count);
    for (std::size_t g = 0; g < group_count; ++g)
        if (const compute::TileGroupSurface* s = get_group(g)) {
            group_index.emplace_back(s->id, out.groups.size());
            renderer::TileGroup tg;
            tg.id = s->id;
            tg.bounds_m = s->bounds_m;
            tg.version = s->version;
            tg.children_cover = s->children_cover;
            tg.levels_waiting = s->levels_waiting;
            const std::size_t first = out.levels.size();
            for (const compute::TileLodLevel& l : s->lods) out.levels.push_back(level_of(l));
            tg.levels = std::span<const renderer::TileMeshLevel>(out.levels.data() + first, s->lods.size());
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
    link_neighbours(group_count, get_group, out);
    out.tiles.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        const compute::TileSurface* s = get(i);
        if (!s) continue;
        renderer::TileMesh tm;
        tm.mesh = &s->mesh;
        tm.bounds_m = s->bounds_m;
        tm.version = s->version;
        tm.id = s->id;
        tm.materials = &s->materials;
        tm.normals = &s->normals;
        if (with_lods && !s->lods.empty()) {
            const std::size_t first = out.levels.size();
            for (const compute::TileLodLevel& l : s->lods) out.levels.push_back(level_of(l));
            tm.levels = std::span<const renderer::TileMeshLevel>(out.levels.data() + first, s->lods.size());
        }
        tm.group = find_index(tile_group, s->id, renderer::TileMesh::kNoGroup);
        out.tiles.push_back(tm);
    }
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
    out.from_tiles.assign(surfaces.begin(), surfaces.end());
    out.from_groups.assign(groups.begin(), groups.end());
    out.from_lods = with_lods;
    out.from_shared = true;
    fill(surfaces.size(), [&](std::size_t i) { return surfaces[i].get(); }, groups.size(),
         [&](std::size_t g) { return groups[g].get(); }, with_lods, out);
}

void tile_view_of(std::span<const compute::TileSurface> surfaces, std::span<const compute::TileGroupSurface> groups,
                  bool with_lods, TileView& out) {
    out.from_tiles.clear();  // these lists change in place: nothing to recognise them by
    out.from_groups.clear();
    out.from_shared = false;
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
