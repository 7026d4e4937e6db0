// compute/contour/held_tiles.hpp - the tile cache refreshed from a contour whose tiles a coarse-first start-up and a
// stroke drawn coarse hold back (docs/design/lod.md, "Coarse first at start-up"; "Strokes drawn coarse").
#pragma once

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"

namespace tridex::compute {

class DeferredContour;
class StartupRefiner;

/// Refreshes `cache` (TileSurfaceCache::refresh) from `contourer`'s tiles as `refiner` (a coarse-first start-up) and
/// `deferral` (a stroke drawn coarse) let them be seen; either may be null (both null: a plain refresh). First the
/// tiles neither holds back any more arrive (TileSurfaceCache::arrive): each reports a tile once, when it stops
/// hiding it, so a tile the other still hides arrives with the other's report. Then the refresh sees every tile
/// either hides as empty. The caller hands the cache its frames' groups (want_detail, frames_drew) before, and drops
/// the refiner once StartupRefiner::done() after. Throws as TileSurfaceCache::refresh.
void refresh_held_tiles(TileSurfaceCache& cache, const Contourer& contourer, StartupRefiner* refiner,
                        DeferredContour* deferral);

}  // namespace tridex::compute
