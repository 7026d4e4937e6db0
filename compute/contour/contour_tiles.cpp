// compute/contour/contour_tiles.cpp - per-tile surface cache over a Contourer.
#include "compute/contour/contour_tiles.hpp"

#include <utility>

namespace tridex::compute {

std::size_t TileSurfaceCache::refresh(const Contourer& contourer) {
    // First build the changed tiles aside, so an exception leaves the cache as it was.
    std::vector<TileSurface> rebuilt;
    std::size_t old = 0;  // walks tiles_ (sorted by id) alongside the tile indices
    const std::size_t count = contourer.tile_count();
    struct Step {
        bool fresh;
        std::size_t index;  // into rebuilt (fresh) or tiles_ (kept)
    };
    std::vector<Step> order;
    for (std::size_t t = 0; t < count; ++t) {
        while (old < tiles_.size() && tiles_[old].id < t) ++old;
        if (contourer.tile_triangle_count(t) == 0) continue;
        const std::uint64_t version = contourer.tile_version(t);
        if (old < tiles_.size() && tiles_[old].id == t && tiles_[old].version == version) {
            order.push_back({false, old});
            continue;
        }
        TileSurface s;
        s.id = t;
        s.version = version;
        s.mesh = contourer.tile_mesh(t, s.materials);
        s.bounds_m = s.mesh.bounds();
        order.push_back({true, rebuilt.size()});
        rebuilt.push_back(std::move(s));
    }
    std::vector<TileSurface> next;
    next.reserve(order.size());
    for (const Step& st : order) next.push_back(std::move(st.fresh ? rebuilt[st.index] : tiles_[st.index]));
    tiles_ = std::move(next);
    return rebuilt.size();
}

std::size_t TileSurfaceCache::triangle_count() const {
    std::size_t n = 0;
    for (const TileSurface& s : tiles_) n += s.mesh.triangles.size();
    return n;
}

}  // namespace tridex::compute
