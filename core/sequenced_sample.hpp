// core/sequenced_sample.hpp - a tool sample with its place in the stream the sculpt thread drains.
#pragma once

#include <cstdint>

#include "core/tool_sample.hpp"

namespace tridex {

/// A ToolSample and its sequence number: 0, 1, 2, ... over the samples the haptic loop handed the sculpt thread, in
/// the order it drains them (what the journal's intake thread receives, HapticLoopConfig::sample_tap).
struct SequencedSample {
    std::uint64_t seq = 0;  ///< the sample's number in the sculpt thread's stream
    ToolSample sample;      ///< the sample, as pushed
};

}  // namespace tridex
