// compute/contour/refine_wanted.cpp - the tiles under wanted groups, contoured a block at a time.
#include "compute/contour/refine_wanted.hpp"

#include <algorithm>
#include <array>
#include <string>

#include "compute/contour/deferred_contour.hpp"
#include "compute/contour/sorted_ids.hpp"
#include "compute/contour/startup_refine.hpp"
#include "core/error.hpp"

namespace tridex::compute {

WantedRefined refine_wanted_groups(std::span<const std::uint64_t> group_ids,
                                   const std::vector<TileGroupSurface>& groups, TriDexel& model, Contourer& contourer,
                                   StartupRefiner* refiner, DeferredContour* deferral, int block_depth,
                                   const std::function<bool()>& in_slice) {
    if (block_depth < 1 || block_depth > 6)
        throw Error("refine_wanted_groups: block_depth must be 1..6, got " + std::to_string(block_depth));
    WantedRefined refined;
    for (const std::uint64_t id : group_ids) {
        if (!in_slice()) break;
        const TileGroupSurface* g = find_by_id(groups, id);
        if (!g || g->children_cover) continue;
        const int depth = std::min(g->depth, block_depth), per = 1 << (g->depth - depth);
        for (int z = 0; z < per && in_slice(); ++z)
            for (int y = 0; y < per && in_slice(); ++y)
                for (int x = 0; x < per && in_slice(); ++x) {
                    const std::array<int, 3> c{g->coords[0] * per + x, g->coords[1] * per + y, g->coords[2] * per + z};
                    if (refiner && !refiner->done())
                        refined.startup += refiner->refine_group(model, contourer, depth, c);
                    if (deferral) refined.deferred += deferral->contour_group(model, contourer, depth, c);
                }
    }
    return refined;
}

}  // namespace tridex::compute
