// compute/journal/journal_writer.cpp - the session journal's writer (write(2) on the caller's thread, fdatasync on a
// syncing thread of its own).
#include "compute/journal/journal_writer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "compute/journal/journal_format.hpp"
#include "core/crc32.hpp"
#include "core/thread_name.hpp"

namespace tridex::compute {

namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }
}  // namespace

JournalWriter::JournalWriter(const std::string& path, const std::string& session, std::chrono::nanoseconds sync_interval,
                             std::size_t buffer_bytes)
    : cap_(std::max<std::size_t>(buffer_bytes, 4096)), interval_(sync_interval) {
    stats_.path = path;
    buf_.reserve(cap_);
    if (session.size() > kJournalMaxSessionBytes) {
        std::lock_guard lock(mutex_);
        error_ = "the session identity is " + std::to_string(session.size()) + " bytes, more than the journal holds";
        failed_.store(true, std::memory_order_release);
        return;
    }
    fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) {
        fail("cannot create the journal", errno);
        return;
    }
    unsigned char head[kJournalHeaderFixedBytes];
    std::memcpy(head, kJournalMagic, 8);
    put_u32(head + 8, kJournalVersion);
    put_u32(head + 12, static_cast<std::uint32_t>(kJournalSampleBytes));
    put_u32(head + 16, static_cast<std::uint32_t>(session.size()));
    crc_ = 0;
    put(head, sizeof head);
    put(reinterpret_cast<const unsigned char*>(session.data()), session.size());
    unsigned char crc[4];
    put_u32(crc, crc_);
    put(crc, 4);
    sync();
    if (ok()) syncer_ = std::thread([this] { run_syncer(); });
}

JournalWriter::~JournalWriter() { close(); }

void JournalWriter::fail(const std::string& what, int err) {
    // The caller's thread: records and bytes are its counters.
    const std::string message = what + " after " + std::to_string(stats_.records) + " records (" +
                                std::to_string(stats_.bytes) + " bytes): " + std::strerror(err);
    std::lock_guard lock(mutex_);
    if (error_.empty()) error_ = message;
    failed_.store(true, std::memory_order_release);
}

std::string JournalWriter::error() const {
    std::lock_guard lock(mutex_);
    return error_;
}

const JournalStats& JournalWriter::stats() const {
    std::lock_guard io(io_mutex_);
    std::lock_guard lock(mutex_);
    stats_.flushes = flushes_;
    stats_.synced_bytes = synced_;
    stats_.sync_thread_ms_total = sync_thread_ms_;
    stats_.error = error_;
    return stats_;
}

void JournalWriter::run_syncer() {
    name_this_thread("tridex-journal");
    // Wakes at each sync point, and on its own at least every interval (1 ms .. 1 s) to make durable what the
    // caller wrote out in between (a full buffer). fdatasync runs without the lock, so the caller never waits.
    const auto period = std::clamp<std::chrono::nanoseconds>(interval_, std::chrono::milliseconds(1), std::chrono::seconds(1));
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait_for(lock, period, [this] { return stop_ || sync_asked_; });
        if (stop_ || !error_.empty()) return;
        sync_asked_ = false;
        if (synced_ >= written_) continue;
        const std::uint64_t target = written_;
        lock.unlock();
        const auto t0 = Clock::now();
        const int rc = ::fdatasync(fd_);
        const int err = errno;
        const double ms = ms_since(t0);
        lock.lock();
        sync_thread_ms_ += ms;
        if (rc != 0) {
            if (error_.empty())
                error_ = "fdatasync failed with " + std::to_string(synced_) + " of " + std::to_string(written_) +
                         " bytes durable: " + std::strerror(err);
            failed_.store(true, std::memory_order_release);
            return;
        }
        synced_ = std::max(synced_, target);
        ++flushes_;
    }
}

void JournalWriter::stop_syncer() {
    if (!syncer_.joinable()) return;
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_one();
    syncer_.join();
}

void JournalWriter::put(const unsigned char* p, std::size_t n) {
    crc_ = crc32_ieee(p, n, crc_);
    while (n > 0 && ok()) {
        if (buf_.size() == cap_ && !write_out()) return;
        const std::size_t k = std::min(n, cap_ - buf_.size());
        buf_.insert(buf_.end(), p, p + k);
        p += k;
        n -= k;
    }
}

bool JournalWriter::write_out() {
    const unsigned char* p = buf_.data();
    std::size_t left = buf_.size();
    const std::uint64_t before = stats_.bytes;
    while (left > 0) {
        const ssize_t w = ::write(fd_, p, left);
        if (w < 0) {
            if (errno == EINTR) continue;
            fail("write failed", errno);
            buf_.clear();
            return false;
        }
        p += w;
        left -= static_cast<std::size_t>(w);
        stats_.bytes += static_cast<std::uint64_t>(w);
    }
    buf_.clear();
    std::lock_guard lock(mutex_);
    written_ += stats_.bytes - before;
    return true;
}

bool JournalWriter::samples_record(std::uint32_t type, std::uint64_t first_seq, std::span<const ToolSample> samples) {
    const std::size_t head_bytes = type == kJournalIntake ? kJournalIntakeHeadBytes : kJournalBatchHeadBytes;
    unsigned char head[kJournalRecordHeadBytes + kJournalIntakeHeadBytes];
    put_u32(head, type);
    put_u32(head + 4, static_cast<std::uint32_t>(head_bytes + samples.size() * kJournalSampleBytes));
    put_u64(head + 8, stats_.records);
    put_u32(head + 16, static_cast<std::uint32_t>(samples.size()));
    put_u32(head + 20, 0);
    if (type == kJournalIntake) put_u64(head + 24, first_seq);
    crc_ = 0;
    put(head, kJournalRecordHeadBytes + head_bytes);
    unsigned char one[kJournalSampleBytes];
    for (const ToolSample& s : samples) {
        encode_sample(s, one);
        put(one, sizeof one);
    }
    unsigned char crc[4];
    put_u32(crc, crc_);
    put(crc, 4);
    if (!ok()) return false;
    ++stats_.records;
    unsynced_ = true;
    return true;
}

void JournalWriter::append(std::span<const ToolSample> samples) {
    std::lock_guard io(io_mutex_);
    if (!ok() || samples.empty()) return;
    const auto t0 = Clock::now();
    if (!samples_record(kJournalBatch, 0, samples)) return;
    stats_.samples += samples.size();
    for (const ToolSample& x : samples) own_samples_ += x.site == 0;  // intake numbers the session's own tool's
    stats_.append_ms_total += ms_since(t0);
    sync_if_due_locked();
}

void JournalWriter::intake(std::uint64_t first_seq, std::span<const ToolSample> samples) {
    std::lock_guard io(io_mutex_);
    if (!ok()) return;
    // Samples a batch record already holds (the sculpt thread caught up) are not written twice.
    const std::uint64_t skip = own_samples_ > first_seq ? own_samples_ - first_seq : 0;
    if (skip >= samples.size()) return;
    samples = samples.subspan(static_cast<std::size_t>(skip));
    if (!samples_record(kJournalIntake, first_seq + skip, samples)) return;
    ++stats_.intake_records;
    stats_.intake_samples += samples.size();
    if (!buf_.empty() && write_out()) last_hand_off_ = Clock::now();
}

void JournalWriter::record(std::uint32_t type, const unsigned char* payload, std::size_t n) {
    if (!ok()) return;
    const auto t0 = Clock::now();
    unsigned char head[kJournalRecordHeadBytes];
    put_u32(head, type);
    put_u32(head + 4, static_cast<std::uint32_t>(n));
    crc_ = 0;
    put(head, sizeof head);
    put(payload, n);
    unsigned char crc[4];
    put_u32(crc, crc_);
    put(crc, 4);
    if (!ok()) return;
    ++stats_.records;
    unsynced_ = true;
    stats_.append_ms_total += ms_since(t0);
}

void JournalWriter::mark(std::uint32_t type, std::uint64_t serial, std::uint64_t rays) {
    std::lock_guard io(io_mutex_);
    if (type != kJournalStrokeEnd && type != kJournalUndo && type != kJournalRedo && type != kJournalLattice) return;
    unsigned char p[kJournalMarkBytes];
    put_u64(p, stats_.records);
    put_u64(p + 8, serial);
    put_u64(p + 16, rays);
    record(type, p, sizeof p);
    sync_if_due_locked();
}

void JournalWriter::checkpoint(const std::string& name, std::uint64_t bytes, std::uint32_t crc) {
    std::lock_guard io(io_mutex_);
    if (name.empty() || name.size() > kJournalMaxNameBytes) return;
    std::vector<unsigned char> p(kJournalCheckpointHeadBytes + name.size());
    put_u64(p.data(), stats_.records);
    put_u64(p.data() + 8, bytes);
    put_u32(p.data() + 16, crc);
    put_u32(p.data() + 20, static_cast<std::uint32_t>(name.size()));
    std::memcpy(p.data() + kJournalCheckpointHeadBytes, name.data(), name.size());
    record(kJournalCheckpoint, p.data(), p.size());
    sync_locked();
}

void JournalWriter::sync_if_due() {
    std::lock_guard io(io_mutex_);
    sync_if_due_locked();
}

void JournalWriter::sync_if_due_locked() {
    if (!unsynced_ || !ok()) return;
    const auto t0 = Clock::now();
    // What is handed to the kernel survives the process being killed; only durability waits for the sync interval.
    if (!buf_.empty() && t0 - last_hand_off_ >= kHandOffInterval) {
        if (!write_out()) return;
        last_hand_off_ = t0;
    }
    if (t0 - last_sync_ < interval_) return;
    if (!buf_.empty() && !write_out()) return;
    {
        std::lock_guard lock(mutex_);
        sync_asked_ = true;
    }
    wake_.notify_one();  // the syncing thread fdatasyncs; this thread goes on
    unsynced_ = false;
    last_sync_ = t0;
    stats_.flush_ms_total += ms_since(t0);
}

void JournalWriter::sync() {
    std::lock_guard io(io_mutex_);
    sync_locked();
}

void JournalWriter::sync_locked() {
    if (!ok()) return;
    const auto t0 = Clock::now();
    if (!buf_.empty() && !write_out()) return;
    std::uint64_t target = 0;
    bool durable = false;
    {
        std::lock_guard lock(mutex_);
        target = written_;
        durable = synced_ >= target;
    }
    if (!durable) {
        if (::fdatasync(fd_) != 0) {
            fail("fdatasync failed", errno);
            return;
        }
        std::lock_guard lock(mutex_);
        synced_ = std::max(synced_, target);
        ++flushes_;
    }
    unsynced_ = false;
    last_sync_ = Clock::now();
    stats_.flush_ms_total += ms_since(t0);
}

void JournalWriter::close() {
    std::lock_guard io(io_mutex_);
    if (fd_ < 0) return;
    stop_syncer();
    sync_locked();
    ::close(fd_);
    fd_ = -1;
}

}  // namespace tridex::compute
