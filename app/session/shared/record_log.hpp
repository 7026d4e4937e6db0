// app/session/shared/record_log.hpp - the host's copy of its stream's records, for joiners that start before the
// newest record (from the session's start, or from a snapshot taken a few records ago), kept packed with zstd in chunks
// so that an hours-long session does not hold every sample as it is.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "compute/journal/journal_reader.hpp"

namespace tridex::app {

/// Every record of a stream in order, from index 0: whole chunks of kChunkRecords records packed with zstd
/// (encode_records' packed form), the records after the last whole chunk as they are. Not thread-safe.
class RecordLog {
public:
    static constexpr std::size_t kChunkRecords = 1024;  ///< records per packed chunk

    /// Appends `records` (the stream's next ones, in order); packs each chunk it completes.
    void append(std::vector<compute::JournalRecord>&& records);
    /// Records so far (the next record's index).
    std::size_t size() const { return packed_.size() * kChunkRecords + tail_.size(); }
    /// Records [from, from + n) (n cut at size()), unpacked. Throws tridex::Error when a chunk does not unpack (not
    /// expected: the log packed it itself).
    std::vector<compute::JournalRecord> read(std::size_t from, std::size_t n) const;
    /// Bytes the log holds (the packed chunks, and the unpacked records' samples).
    std::size_t bytes() const;

private:
    std::vector<std::vector<unsigned char>> packed_;  // chunk k: records [k * kChunkRecords, (k + 1) * kChunkRecords)
    std::vector<compute::JournalRecord> tail_;        // the records after the last whole chunk
    std::size_t packed_bytes_ = 0;
};

}  // namespace tridex::app
