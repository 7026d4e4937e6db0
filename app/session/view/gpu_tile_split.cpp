// app/session/view/gpu_tile_split.cpp - GPU contour tiles: read-back levels of detail or indirect draws.
#include "app/session/view/gpu_tile_split.hpp"

#include <unordered_set>

namespace tridex::app {

void split_gpu_tiles(std::span<const std::shared_ptr<const compute::TileSurface>> tiles,
                     std::span<const std::shared_ptr<const compute::TileGroupSurface>> groups,
                     renderer::IndirectWorkpiece& indirect, GpuTileSplit& out) {
    out.tiles.clear();
    out.groups.clear();
    std::unordered_set<std::uint64_t> taken;  // ids of the tiles and groups drawn from the read-back surface
    std::vector<renderer::IndirectTile> left;
    left.reserve(indirect.tiles.size());
    std::size_t k = 0;  // walks `tiles` (by id) alongside indirect.tiles (by id)
    for (const renderer::IndirectTile& t : indirect.tiles) {
        while (k < tiles.size() && (!tiles[k] || tiles[k]->id < t.id)) ++k;
        const bool current = k < tiles.size() && tiles[k]->id == t.id && tiles[k]->lods_built &&
                             tiles[k]->source_version == t.version && t.version != 0;
        if (!current) {
            left.push_back(t);
            continue;
        }
        out.tiles.push_back(tiles[k]);
        taken.insert(t.id);
    }
    indirect.tiles = std::move(left);
    // Groups by id: finer depths first, so a group's smaller groups are decided before it.
    for (const std::shared_ptr<const compute::TileGroupSurface>& g : groups) {
        if (!g || g->children.empty()) continue;
        bool all = true;
        for (const std::uint64_t c : g->children)
            if (!taken.contains(c)) {
                all = false;
                break;
            }
        if (!all) continue;
        out.groups.push_back(g);
        taken.insert(g->id);
    }
}

}  // namespace tridex::app
