// bench/bench_verdict.hpp - a benchmark row's verdict against its target: met, over target, or not measured. A row
// whose target had no timed sample says so and does not count as met: the quantiles of no samples read 0, which would
// otherwise pass any upper bound.
#pragma once

#include <cstddef>

namespace tridex::bench {

/// What a row with a target says of it.
enum class Verdict {
    kMet,          ///< timed, and within the target
    kOver,         ///< timed, and over it
    kNotMeasured,  ///< nothing the target reads was timed
};

/// kNotMeasured when `timed` (the samples the target's figures come from) is 0; else kMet when `within` (those
/// figures are within the target), else kOver.
Verdict verdict_of(std::size_t timed, bool within);

/// The verdict as the tables print it: "target met", "over target" or "not measured".
const char* verdict_text(Verdict v);

/// Whether the row counts as having met its target (its JSON's target_met): kMet only.
inline bool target_met(Verdict v) { return v == Verdict::kMet; }

}  // namespace tridex::bench
