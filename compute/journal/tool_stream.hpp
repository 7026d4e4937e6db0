// compute/journal/tool_stream.hpp - a listener to the stream of tool samples and marks the sculpt thread applies: the
// stream that determines the model (DESIGN.md, persistence), for replicating it elsewhere as it is made.
#pragma once

#include <cstdint>
#include <span>

#include "core/tool_sample.hpp"

namespace tridex::compute {

struct TriDexel;

/// Receives, on the sculpt thread, what the session journal receives, in the same order: each batch of samples
/// after it was applied (one call per journal batch record) and each stroke-end, undo, redo or lattice mark (type
/// kJournalStrokeEnd, kJournalUndo, kJournalRedo or kJournalLattice of journal_format.hpp, the step's serial, the
/// rays written back or the new resolution), then after_record() with the model as it stands after that record. Applying the same calls, in order,
/// through journal_apply's rules gives the same model bit for bit. Implementations must be quick (the sculpt thread
/// waits) and must not throw.
class ToolStreamSink {
public:
    virtual ~ToolStreamSink() = default;
    /// One batch of samples, as applied (never empty).
    virtual void append(std::span<const ToolSample> samples) = 0;
    /// One mark: type, stroke serial, rays written back (0 for a stroke end).
    virtual void mark(std::uint32_t type, std::uint64_t serial, std::uint64_t rays) = 0;
    /// After each append() or mark(): the model holding every record so far (read only; the call is on the thread
    /// that owns the model, so it may be read here and nowhere else).
    virtual void after_record(const TriDexel& model) { (void)model; }
};

}  // namespace tridex::compute
