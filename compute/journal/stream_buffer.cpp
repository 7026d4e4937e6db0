// compute/journal/stream_buffer.cpp - records handed from the sculpt thread to another under a mutex.
#include "compute/journal/stream_buffer.hpp"

#include <algorithm>
#include <cmath>

#include "compute/journal/journal_format.hpp"
#include "compute/model/model_digest.hpp"

namespace tridex::compute {

void ToolStreamBuffer::append(std::span<const ToolSample> samples) {
    JournalRecord r;
    r.kind = JournalKind::kBatch;
    r.samples.assign(samples.begin(), samples.end());
    double newest = 0.0;
    for (const ToolSample& s : samples)
        if (std::isfinite(s.made_s)) newest = std::max(newest, s.made_s);
    std::lock_guard<std::mutex> lock(mutex_);
    r.index = next_index_++;
    pending_.samples += samples.size();
    pending_.newest_made_s = std::max(pending_.newest_made_s, newest);
    pending_.records.push_back(std::move(r));
}

void ToolStreamBuffer::mark(std::uint32_t type, std::uint64_t serial, std::uint64_t rays) {
    JournalRecord r;
    r.kind = type == kJournalUndo      ? JournalKind::kUndo
             : type == kJournalRedo    ? JournalKind::kRedo
             : type == kJournalLattice ? JournalKind::kLattice
                                       : JournalKind::kStrokeEnd;
    r.serial = serial;
    r.rays = rays;
    std::lock_guard<std::mutex> lock(mutex_);
    r.index = next_index_++;
    pending_.records.push_back(std::move(r));
}

void ToolStreamBuffer::after_record(const TriDexel& model) {
    if (!digest_wanted_.exchange(false, std::memory_order_acq_rel)) return;
    const std::uint64_t d = model_digest(model);  // on the sculpt thread, which owns the model
    std::lock_guard<std::mutex> lock(mutex_);
    if (pending_.digest) return;  // one check per frame message
    pending_.digest = d;
    pending_.digest_after = static_cast<std::uint32_t>(pending_.records.size());
}

ToolStreamBuffer::Taken ToolStreamBuffer::take() {
    std::lock_guard<std::mutex> lock(mutex_);
    Taken out = std::move(pending_);
    pending_ = Taken{};
    return out;
}

std::uint64_t ToolStreamBuffer::records() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return next_index_;
}

}  // namespace tridex::compute
