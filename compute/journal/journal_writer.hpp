// compute/journal/journal_writer.hpp - appending the sculpt thread's batches of ToolSamples to a session journal
// file (compute/journal/journal_format.hpp), made durable at least every sync interval by a syncing thread of its own.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "core/tool_sample.hpp"

namespace tridex::compute {

/// What a JournalWriter did (report.json `journal`).
struct JournalStats {
    std::string path;              ///< the journal file
    std::uint64_t records = 0;     ///< records appended (written to the file or still buffered): all kinds
    std::uint64_t samples = 0;     ///< tool samples in batch records
    std::uint64_t intake_records = 0;  ///< intake records appended (intake())
    std::uint64_t intake_samples = 0;  ///< samples in them (received before a batch record held them)
    std::uint64_t bytes = 0;       ///< bytes handed to write(2) successfully, header included
    std::uint64_t synced_bytes = 0;///< of those, bytes made durable by a successful fdatasync
    std::uint64_t flushes = 0;     ///< fdatasync rounds that succeeded (the syncing thread's and sync()'s)
    /// Caller's (the sculpt thread's) wall time encoding records (and writing out a full buffer), ms.
    double append_ms_total = 0.0;
    /// Caller's wall time at sync points: writing the buffer out and waking the syncing thread (sync_if_due), and
    /// sync() / close(), which also wait for fdatasync, ms. append_ms_total + flush_ms_total is the journal's cost on
    /// the caller's thread.
    double flush_ms_total = 0.0;
    /// Wall time the writer's own syncing thread spent in fdatasync, off the caller's thread, ms.
    double sync_thread_ms_total = 0.0;
    /// Why the journal stopped ("" while it works): e.g. "write failed after 12 records: No space left on
    /// device". After an error nothing more is written; the session goes on.
    std::string error;
};

/// Writes a session journal: the header at construction, then one record per append() (one sculpt step's
/// batch, in order), through a buffer of fixed size reserved up front (no allocation per batch). The caller's
/// thread only encodes records and hands them to the kernel with write(2): when the buffer fills, at least every
/// kHandOffInterval, and at sync points, at least every `sync_interval` of wall time while appends come (append,
/// mark and sync_if_due check the clock; a caller that idles calls sync_if_due). fdatasync runs on a syncing thread the writer owns: woken at each sync
/// point, and on its own at least every sync_interval (at most every second) while written bytes are not yet durable,
/// so what was appended is durable within about one interval (plus the fdatasync) without the caller ever waiting
/// for the disk. sync(), checkpoint() and close() sync on the caller's thread and return when the bytes are durable.
/// Never throws after construction: a failed write or sync (disk full, read-only, I/O error), on either thread,
/// stops the journal (nothing more is written; the session goes on) and is recorded in stats().error. Two threads
/// may call it: the sculpt thread (batches, marks, checkpoints, syncs) and one intake thread (intake(),
/// JournalIntake); a lock keeps their records whole and in one order. The syncing thread is internal.
class JournalWriter {
public:
    /// Longest time appended bytes wait in the writer's own buffer before write(2) hands them to the kernel (checked
    /// at each append, mark and sync_if_due).
    static constexpr std::chrono::milliseconds kHandOffInterval{10};

    /// Creates (or truncates) `path` and writes and syncs the header carrying `session` (the caller's identity
    /// of the session, e.g. its spec as JSON; at most kJournalMaxSessionBytes). buffer_bytes (>= 4096) is the
    /// write buffer reserved once. A file that cannot be created or a header that cannot be written does not
    /// throw: the writer starts stopped, with stats().error saying why (ok() false). Starts the syncing thread
    /// when the header is durable.
    JournalWriter(const std::string& path, const std::string& session,
                  std::chrono::nanoseconds sync_interval = std::chrono::milliseconds(100),
                  std::size_t buffer_bytes = std::size_t{1} << 18);
    /// close(): syncs what is buffered, ends the syncing thread and closes the file (errors are recorded, never thrown).
    ~JournalWriter();
    JournalWriter(const JournalWriter&) = delete;
    JournalWriter& operator=(const JournalWriter&) = delete;

    /// Appends one record holding `samples` (may be empty: nothing is written), then sync_if_due(). Any batch size
    /// works: a record larger than the buffer is streamed through it.
    void append(std::span<const ToolSample> samples);
    /// Appends an intake record (journal_format.hpp, kJournalIntake) holding the samples of `samples` that no batch
    /// record holds yet: `samples` are the session's own tool's samples (site 0) numbered first_seq, first_seq + 1, ...
    /// in the order the sculpt thread drains them, and those below the count of site-0 samples appended in batches so
    /// far are left out (nothing is
    /// written when none is left). Then hands every buffered byte to the kernel at once, so a process killed after
    /// it returns keeps them. Called by one thread besides the sculpt thread (JournalIntake).
    void intake(std::uint64_t first_seq, std::span<const ToolSample> samples);
    /// Appends a mark (journal_format.hpp): `type` kJournalStrokeEnd, kJournalUndo, kJournalRedo or kJournalLattice,
    /// the step's serial and (undo, redo) the rays written back or (lattice) the new resolution, then sync_if_due().
    /// Other types are ignored.
    void mark(std::uint32_t type, std::uint64_t serial, std::uint64_t rays = 0);
    /// Appends a checkpoint record naming the model file `name` (a plain file name in the journal's folder; its
    /// size and CRC-32) that holds the model after every record appended so far, and syncs at once (sync()).
    void checkpoint(const std::string& name, std::uint64_t bytes, std::uint32_t crc);
    /// Hands the buffered bytes to the kernel (write(2)) when kHandOffInterval has passed since it last did, so a
    /// process killed (SIGKILL, a crash) loses at most that much of what was appended; and when the sync interval
    /// has passed since the last sync point and something was appended since, wakes the syncing thread to fdatasync
    /// them (durable against a power loss). Never waits for the disk.
    void sync_if_due();
    /// Writes the buffered bytes out and fdatasyncs them now, on the caller's thread (nothing when all is durable).
    void sync();
    /// Ends the syncing thread, then a final sync and close; later appends do nothing. Idempotent.
    void close();
    /// True while the journal is being written (no error on either thread, not closed).
    bool ok() const { return fd_ >= 0 && !failed_.load(std::memory_order_acquire); }
    /// Counters and the error, if any (the syncing thread's counted as of this call). The reference is read safely
    /// only while no other thread appends (after the session, or in a single-threaded use); error() any time.
    const JournalStats& stats() const;
    /// Why the journal stopped ("" while it works); any thread.
    std::string error() const;

private:
    void sync_if_due_locked();
    void sync_locked();
    void record(std::uint32_t type, const unsigned char* payload, std::size_t n);  // one small record, whole
    // A batch or intake record (first_seq: kJournalIntake's); false when the journal stopped on the way.
    bool samples_record(std::uint32_t type, std::uint64_t first_seq, std::span<const ToolSample> samples);
    void put(const unsigned char* p, std::size_t n);  // into the buffer, CRC updated; writes out when full
    bool write_out();                                  // buffer -> write(2); false on error (recorded)
    void fail(const std::string& what, int err);       // either thread: record the first error, stop the journal
    void run_syncer();                                 // the syncing thread
    void stop_syncer();

    // The callers' (sculpt and intake threads'), under io_mutex_:
    std::uint64_t own_samples_ = 0;  // site-0 samples appended in batches: what intake() numbers
    mutable std::mutex io_mutex_;     // taken before mutex_
    int fd_ = -1;
    std::vector<unsigned char> buf_;  // reserved once; size() = bytes pending
    std::size_t cap_ = 0;
    std::uint32_t crc_ = 0;           // running CRC of the record being put
    bool unsynced_ = false;           // appended since the last sync point
    std::chrono::nanoseconds interval_;
    std::chrono::steady_clock::time_point last_sync_;
    std::chrono::steady_clock::time_point last_hand_off_;  // the last write(2) of sync_if_due
    mutable JournalStats stats_;      // stats() adds the shared counters below

    // Shared with the syncing thread, under mutex_:
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::uint64_t written_ = 0;       // bytes handed to write(2)
    std::uint64_t synced_ = 0;        // of those, bytes made durable by a successful fdatasync
    bool sync_asked_ = false;         // a sync point asked for an fdatasync
    bool stop_ = false;               // close(): the syncing thread ends
    std::uint64_t flushes_ = 0;
    double sync_thread_ms_ = 0.0;
    std::string error_;               // the first error, from either thread
    std::atomic<bool> failed_{false}; // error_ is set
    std::thread syncer_;
};

}  // namespace tridex::compute
