// compute/journal/stream_buffer.hpp - the sculpt thread's stream of records kept for another thread to take: what a
// cluster's rank 0 sends its render ranks each frame.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include "compute/journal/journal_reader.hpp"
#include "compute/journal/tool_stream.hpp"

namespace tridex::compute {

/// The sculpt thread's stream as journal records (batches and marks in order, indices 0, 1, ...) and, when asked,
/// the model's digest (model_digest) after the next record. Fed on the sculpt thread, taken on another; thread-safe.
class ToolStreamBuffer final : public ToolStreamSink {
public:
    void append(std::span<const ToolSample> samples) override;
    void mark(std::uint32_t type, std::uint64_t serial, std::uint64_t rays) override;
    void after_record(const TriDexel& model) override;

    /// Asks for the model's digest after the next record (served by the sculpt thread).
    void request_digest() { digest_wanted_.store(true, std::memory_order_release); }
    /// Everything since the last take: the records, and the digest check if one was served (after how many of
    /// them); the newest sample's made_s (0 when none).
    struct Taken {
        std::vector<JournalRecord> records;
        std::optional<std::uint64_t> digest;
        std::uint32_t digest_after = 0;
        double newest_made_s = 0.0;
        std::size_t samples = 0;
    };
    Taken take();
    /// Records handed out so far (the next record's index).
    std::uint64_t records() const;

private:
    mutable std::mutex mutex_;
    Taken pending_;
    std::uint64_t next_index_ = 0;
    std::atomic<bool> digest_wanted_{false};
};

}  // namespace tridex::compute
