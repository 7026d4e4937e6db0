// compute/journal/journal_writer.hpp - appending the sculpt thread's batches of ToolSamples to a session journal
// file (compute/journal/journal_format.hpp), made durable at least every sync interval.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/tool_sample.hpp"

namespace tridex::compute {

/// What a JournalWriter did (report.json `journal`).
struct JournalStats {
    std::string path;              ///< the journal file
    std::uint64_t records = 0;     ///< records appended (written to the file or still buffered): batches and marks
    std::uint64_t samples = 0;     ///< tool samples in those records
    std::uint64_t bytes = 0;       ///< bytes handed to write(2) successfully, header included
    std::uint64_t flushes = 0;     ///< write + fdatasync rounds that succeeded
    double append_ms_total = 0.0;  ///< wall time spent encoding records (and writing out a full buffer), ms
    double flush_ms_total = 0.0;   ///< wall time spent in write + fdatasync at sync points, ms
    /// Why the journal stopped ("" while it works): e.g. "write failed after 12 records: No space left on
    /// device". After an error nothing more is written; the session goes on.
    std::string error;
};

/// Writes a session journal: the header at construction, then one record per append() (one sculpt step's
/// batch, in order), through a buffer of fixed size reserved up front (no allocation per batch), written with
/// write(2) and made durable with fdatasync at least every `sync_interval` of wall time while appends come
/// (append and sync_if_due check the clock; a caller that idles calls sync_if_due). Never throws after
/// construction: a failed write or sync (disk full, read-only, I/O error) stops the journal and is recorded in
/// stats().error. Not thread-safe: one thread (the sculpt thread) uses it.
class JournalWriter {
public:
    /// Creates (or truncates) `path` and writes and syncs the header carrying `session` (the caller's identity
    /// of the session, e.g. its spec as JSON; at most kJournalMaxSessionBytes). buffer_bytes (>= 4096) is the
    /// write buffer reserved once. A file that cannot be created or a header that cannot be written does not
    /// throw: the writer starts stopped, with stats().error saying why (ok() false).
    JournalWriter(const std::string& path, const std::string& session,
                  std::chrono::nanoseconds sync_interval = std::chrono::milliseconds(100),
                  std::size_t buffer_bytes = std::size_t{1} << 18);
    /// Syncs what is buffered and closes the file (errors are recorded, never thrown).
    ~JournalWriter();
    JournalWriter(const JournalWriter&) = delete;
    JournalWriter& operator=(const JournalWriter&) = delete;

    /// Appends one record holding `samples` (may be empty: nothing is written), then syncs when the interval
    /// since the last sync has passed. Any batch size works: a record larger than the buffer is streamed
    /// through it.
    void append(std::span<const ToolSample> samples);
    /// Appends a mark (journal_format.hpp): `type` kJournalStrokeEnd, kJournalUndo or kJournalRedo, the stroke's
    /// serial and (undo, redo) the rays written back. Syncs when due. Other types are ignored.
    void mark(std::uint32_t type, std::uint64_t serial, std::uint64_t rays = 0);
    /// Appends a checkpoint record naming the model file `name` (a plain file name in the journal's folder; its
    /// size and CRC-32) that holds the model after every record appended so far, and syncs at once.
    void checkpoint(const std::string& name, std::uint64_t bytes, std::uint32_t crc);
    /// Writes and fdatasyncs the buffered bytes when the sync interval has passed since the last sync and
    /// something is unsynced.
    void sync_if_due();
    /// Writes and fdatasyncs the buffered bytes now (nothing when all is synced).
    void sync();
    /// Final sync and close; later appends do nothing. Idempotent.
    void close();
    /// True while the journal is being written (no error, not closed).
    bool ok() const { return fd_ >= 0 && stats_.error.empty(); }
    /// Counters and the error, if any.
    const JournalStats& stats() const { return stats_; }

private:
    void record(std::uint32_t type, const unsigned char* payload, std::size_t n);  // one small record, whole
    void put(const unsigned char* p, std::size_t n);  // into the buffer, CRC updated; writes out when full
    bool write_out();                                  // buffer -> write(2); false on error (recorded)
    void fail(const std::string& what, int err);

    int fd_ = -1;
    std::vector<unsigned char> buf_;  // reserved once; size() = bytes pending
    std::size_t cap_ = 0;
    std::uint32_t crc_ = 0;           // running CRC of the record being put
    bool unsynced_ = false;           // bytes written or buffered since the last fdatasync
    std::chrono::nanoseconds interval_;
    std::chrono::steady_clock::time_point last_sync_;
    JournalStats stats_;
};

}  // namespace tridex::compute
