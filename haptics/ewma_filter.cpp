// haptics/ewma_filter.cpp - parameter check of the EWMA force filter.
#include "haptics/ewma_filter.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tridex::haptics {

EwmaFilter::EwmaFilter(double alpha) : alpha_(alpha) {
    if (!(std::isfinite(alpha) && alpha >= 0.0 && alpha < 1.0))
        throw Error("ewma_alpha = " + std::to_string(alpha) + " must be in [0, 1)");
}

}  // namespace tridex::haptics
