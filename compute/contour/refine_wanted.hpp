// compute/contour/refine_wanted.hpp - the full-resolution tiles under the groups the frames want finer, contoured a
// block at a time (docs/design/lod.md, "Coarse first at start-up"; "Strokes drawn coarse").
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/model/tridexel.hpp"

namespace tridex::compute {

class DeferredContour;
class StartupRefiner;

/// The depth of the tile blocks a wanted group is contoured by between strokes (4x4x4 tiles): a depth-4 group's
/// blocks each fit a pass's slice (the sculpt thread's, a cluster render rank's).
inline constexpr int kWantedBlockDepth = 2;

/// Tiles refine_wanted_groups contoured, by who held them back.
struct WantedRefined {
    std::size_t startup = 0;   ///< a coarse-first start-up's tiles (StartupRefiner::refine_group)
    std::size_t deferred = 0;  ///< a stroke's deferred tiles (DeferredContour::contour_group)
};

/// Contours, with `contourer` (bound to `model`, whose dirty flags must be clear), the tiles that `refiner` (start-up)
/// or `deferral` (a stroke drawn coarse) still hold back under each group of `group_ids` (compute::tile_group_id,
/// ascending, so finest depth first), a block of depth min(group depth, block_depth) at a time, as long as
/// in_slice() says true before each block (a depth-4 group holds hundreds of surface tiles; blocks already contoured
/// cost a scan of their tiles). Ids not in `groups` (ascending by id, TileSurfaceCache::groups) and groups whose
/// children cover them (TileGroupSurface::children_cover: a finer level stands in now) are skipped; a null refiner or
/// deferral holds nothing back. Throws tridex::Error when block_depth is outside 1..6; otherwise as Contourer::update.
WantedRefined refine_wanted_groups(std::span<const std::uint64_t> group_ids,
                                   const std::vector<TileGroupSurface>& groups, TriDexel& model, Contourer& contourer,
                                   StartupRefiner* refiner, DeferredContour* deferral, int block_depth,
                                   const std::function<bool()>& in_slice);

}  // namespace tridex::compute
