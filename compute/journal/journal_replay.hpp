// compute/journal/journal_replay.hpp - applying a journal's records to a model, as the sculpt thread applied them.
#pragma once

#include <cstdint>
#include <span>

#include "compute/journal/journal_reader.hpp"
#include "compute/model/tridexel.hpp"

namespace tridex::compute {

/// What journal_apply did.
struct JournalApplyStats {
    std::uint64_t records = 0;   ///< records applied
    std::uint64_t samples = 0;   ///< samples read
    std::uint64_t booleans = 0;  ///< swept Booleans applied (one per consecutive pair with an op)
    double last_t_s = 0.0;       ///< t_s of the last sample (device time, s); 0 without samples
};

/// Applies `records` in order to `model` through the CPU reference Booleans, one batch per record as the sculpt
/// thread did (sample_sweep between consecutive samples, across record boundaries; each batch validated before
/// any of it changes the model), marking dirty tiles. Sessions have no mesh tools: a kMesh sample throws.
/// Throws tridex::Error naming the record on a sweep the Booleans refuse (the model then holds the records
/// before it).
JournalApplyStats journal_apply(TriDexel& model, std::span<const JournalRecord> records);

}  // namespace tridex::compute
