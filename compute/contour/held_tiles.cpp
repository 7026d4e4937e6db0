// compute/contour/held_tiles.cpp - the tile cache refreshed through start-up's refinement and a stroke's deferral.
#include "compute/contour/held_tiles.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

#include "compute/contour/deferred_contour.hpp"
#include "compute/contour/startup_refine.hpp"

namespace tridex::compute {

void refresh_held_tiles(TileSurfaceCache& cache, const Contourer& contourer, StartupRefiner* refiner,
                        DeferredContour* deferral) {
    if (!refiner && !deferral) {
        cache.refresh(contourer);
        return;
    }
    std::vector<std::uint64_t> arrivals;
    if (refiner)
        for (const std::uint64_t t : refiner->take_newly_publishable())
            if (!deferral || !deferral->hidden(t)) arrivals.push_back(t);
    if (deferral)
        for (const std::uint64_t t : deferral->take_visible())
            if (!refiner || refiner->publishable(t)) arrivals.push_back(t);
    std::sort(arrivals.begin(), arrivals.end());
    arrivals.erase(std::unique(arrivals.begin(), arrivals.end()), arrivals.end());
    cache.arrive(arrivals);
    if (refiner) {
        const StartupRefiner::Source startup(contourer, *refiner);
        if (deferral)
            cache.refresh(DeferredContour::Source(startup, *deferral));
        else
            cache.refresh(startup);
    } else {
        cache.refresh(DeferredContour::Source(ContourerTiles(contourer), *deferral));
    }
}

}  // namespace tridex::compute
