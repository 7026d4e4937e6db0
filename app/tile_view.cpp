// app/tile_view.cpp - TileSurface -> renderer::TileMesh.
#include "app/tile_view.hpp"

namespace tridex::app {
namespace {

template <typename Get>
void fill(std::size_t count, Get&& get, bool with_lods, TileView& out) {
    out.tiles.clear();
    out.levels.clear();
    std::size_t level_count = 0;
    for (std::size_t i = 0; i < count; ++i)
        if (const compute::TileSurface* s = get(i); s && with_lods) level_count += s->lods.size();
    out.levels.reserve(level_count);  // the spans below point into it: no reallocation after this
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
            for (const compute::TileLodLevel& l : s->lods)
                out.levels.push_back(renderer::TileMeshLevel{&l.mesh, l.materials.empty() ? nullptr : &l.materials,
                                                             &l.normals, l.error_m});
            tm.levels = std::span<const renderer::TileMeshLevel>(out.levels.data() + first, s->lods.size());
        }
        out.tiles.push_back(tm);
    }
}

}  // namespace

void tile_view_of(std::span<const std::shared_ptr<const compute::TileSurface>> surfaces, bool with_lods, TileView& out) {
    fill(surfaces.size(), [&](std::size_t i) { return surfaces[i].get(); }, with_lods, out);
}

void tile_view_of(std::span<const compute::TileSurface> surfaces, bool with_lods, TileView& out) {
    fill(surfaces.size(), [&](std::size_t i) { return &surfaces[i]; }, with_lods, out);
}

}  // namespace tridex::app
