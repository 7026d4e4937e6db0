// app/commands/resample/resample.hpp - `tridex resample MODEL.tdx --resolution N --out NEW.tdx`: a saved model
// re-sampled onto a finer or coarser lattice over the same box, its materials and palette kept.
#pragma once

#include <cstddef>
#include <string>

#include "compute/tools/model_resample.hpp"

namespace tridex::app {

/// Options of `tridex resample`.
struct ResampleOptions {
    std::string model;       ///< the saved model to read (.tdx)
    std::string resolution;  ///< the new resolution as typed: cells along the longest axis (a whole number)
    std::string out;         ///< the model file to write (.tdx); must not be `model`
};

/// What a resample did: the library's figures (volumes, surface move, rays by rule) and the file written.
struct ResampleResult {
    compute::ResampleStats stats;
    std::size_t bytes_before = 0;  ///< estimated size of the old model in memory, bytes
};

/// Parses `text` as a resolution: a whole number in [kResampleMinResolution, kResampleMaxResolution]. Throws
/// tridex::Error "--resolution: ..." naming what was typed otherwise.
int parse_resolution(const std::string& text);

/// Reads the model (compute::load_tdx), re-samples it (compute::resample_model, with the memory budget left beside
/// the old model), measures the surface move (compute::measure_surface_move), writes the new model with the old one's
/// transform, settings (their "resolution" updated) and palette atomically (compute::save_tdx) and prints what
/// changed: the volume (m^3 and %), the largest surface move (m and coarse cells) and the new model's memory. Throws
/// tridex::Error with one line naming the file or option at fault: an unreadable model, a bad resolution, a lattice
/// that does not fit in memory (with the MiB it would take), an output that cannot be written.
ResampleResult run_resample(const ResampleOptions& options);

}  // namespace tridex::app
