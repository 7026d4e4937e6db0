// app/session/shared/record_log.cpp - the host's stream log, packed in chunks.
#include "app/session/shared/record_log.hpp"

#include <algorithm>

#include "app/session/shared/shared_message.hpp"

namespace tridex::app {

void RecordLog::append(std::vector<compute::JournalRecord>&& records) {
    for (compute::JournalRecord& r : records) {
        tail_.push_back(std::move(r));
        if (tail_.size() < kChunkRecords) continue;
        RecordsMessage m;
        m.records.swap(tail_);
        packed_.push_back(encode_records(m));
        packed_bytes_ += packed_.back().size();
    }
}

std::vector<compute::JournalRecord> RecordLog::read(std::size_t from, std::size_t n) const {
    std::vector<compute::JournalRecord> out;
    const std::size_t end = std::min(size(), from + n);
    for (std::size_t at = from; at < end;) {
        const std::size_t chunk = at / kChunkRecords;
        if (chunk < packed_.size()) {
            const RecordsMessage m = decode_records(packed_[chunk], "the host's stream log");
            const std::size_t first = at - chunk * kChunkRecords;
            const std::size_t take = std::min(end - at, kChunkRecords - first);
            out.insert(out.end(), m.records.begin() + static_cast<std::ptrdiff_t>(first),
                       m.records.begin() + static_cast<std::ptrdiff_t>(first + take));
            at += take;
        } else {
            const std::size_t first = at - packed_.size() * kChunkRecords;
            out.insert(out.end(), tail_.begin() + static_cast<std::ptrdiff_t>(first),
                       tail_.begin() + static_cast<std::ptrdiff_t>(first + (end - at)));
            at = end;
        }
    }
    return out;
}

std::size_t RecordLog::bytes() const {
    std::size_t b = packed_bytes_ + packed_.size() * sizeof(std::vector<unsigned char>);
    for (const compute::JournalRecord& r : tail_) b += sizeof r + r.samples.size() * sizeof(ToolSample);
    return b;
}

}  // namespace tridex::app
