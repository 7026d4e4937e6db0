// app/session/view/tile_view.cpp - TileSurface / TileGroupSurface -> renderer::TileMesh / TileGroup.
#include "app/session/view/tile_view.hpp"

#include <unordered_map>

#include "compute/contour/lod_worker.hpp"
#include "core/error.hpp"

namespace tridex::app {
namespace {

renderer::TileMeshLevel level_of(const compute::TileLodLevel& l) {
    return renderer::TileMeshLevel{&l.mesh, l.materials.empty() ? nullptr : &l.materials, &l.normals, l.error_m};
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
    std::unordered_map<std::uint64_t, std::size_t> group_index;  // group id -> index in out.groups
    for (std::size_t g = 0; g < group_count; ++g)
        if (const compute::TileGroupSurface* s = get_group(g)) {
            group_index.emplace(s->id, out.groups.size());
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
    std::unordered_map<std::uint64_t, std::size_t> tile_group;  // tile id -> index of its depth-1 group
    for (std::size_t g = 0; g < group_count; ++g)
        if (const compute::TileGroupSurface* s = get_group(g)) {
            const std::size_t at = group_index.at(s->id);
            if (const auto p = group_index.find(s->parent); p != group_index.end()) out.groups[at].parent = p->second;
            if (s->depth == 1)
                for (const std::uint64_t t : s->children) tile_group.emplace(t, at);
        }
    for (std::size_t i = 0; i < count; ++i) {
        const compute::TileSurface* s = get(i);
        if (!s) continue;
        renderer::TileMesh tm;
        tm.mesh = &s->mesh;
        tm.bounds_m = s->bounds_m;
        tm.version = s->version;
        tm.id = s->id;
        tm.materials = &s->materials;
        if (with_lods && !s->lods.empty()) {
            const std::size_t first = out.levels.size();
            for (const compute::TileLodLevel& l : s->lods) out.levels.push_back(level_of(l));
            tm.levels = std::span<const renderer::TileMeshLevel>(out.levels.data() + first, s->lods.size());
        }
        if (const auto g = tile_group.find(s->id); g != tile_group.end()) tm.group = g->second;
        out.tiles.push_back(tm);
    }
}

}  // namespace

void tile_view_of(std::span<const std::shared_ptr<const compute::TileSurface>> surfaces,
                  std::span<const std::shared_ptr<const compute::TileGroupSurface>> groups, bool with_lods,
                  TileView& out) {
    fill(surfaces.size(), [&](std::size_t i) { return surfaces[i].get(); }, groups.size(),
         [&](std::size_t g) { return groups[g].get(); }, with_lods, out);
}

void tile_view_of(std::span<const compute::TileSurface> surfaces, std::span<const compute::TileGroupSurface> groups,
                  bool with_lods, TileView& out) {
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
