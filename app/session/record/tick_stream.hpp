// app/session/record/tick_stream.hpp - a session's recording streamed to disk while it runs, so a recording has no length
// limit and its memory stays bounded.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdio>
#include <span>
#include <string>
#include <thread>

#include "app/scene/session_spec.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/spsc_ring.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app {

/// The ticks of a session's recording on their way to disk. The haptic loop pushes every tick's record into ring()
/// (HapticLoopConfig::record_stream, never waiting: a full ring drops the record, counted by the loop); a thread
/// converts each to a RecordedTick (to_recorded_tick) and appends it to an unnamed temporary file in the
/// recording's folder (O_TMPFILE; an anonymous tmpfile where the folder's file system has none). finish() writes
/// the recording file (TRDXREC, devices/recording.hpp, atomically) from it, with the header the session knows only at
/// its end (the sculpt thread's marks). Memory: the ring's kRingTicks records, whatever the session's length.
class TickStream {
public:
    /// Records the ring holds: 8 s of ticks at 1 kHz, far more than the thread ever lags behind.
    static constexpr std::size_t kRingTicks = 8192;

    /// Opens the temporary file for the recording `path` of a session of `spec`. Throws tridex::Error
    /// "<path>: cannot open a temporary file ..." when its folder cannot hold one.
    TickStream(const SessionSpec& spec, std::string path);
    /// Stops the thread; the temporary file goes with the object (nothing is left on disk).
    ~TickStream();
    TickStream(const TickStream&) = delete;
    TickStream& operator=(const TickStream&) = delete;

    /// The ring the haptic loop pushes into (HapticLoopConfig::record_stream); the loop is its only producer.
    SpscRing<haptics::TickRecord>& ring() { return ring_; }
    /// Starts the thread that drains the ring to the temporary file. Once only.
    void start();
    /// After the loop stopped: drains what is left and stops the thread. Idempotent.
    void stop();
    /// Ticks written to the temporary file so far (any thread).
    std::size_t ticks() const { return ticks_.load(std::memory_order_relaxed); }
    /// After stop(): writes the recording to path() (devices::RecordingWriter, atomically) with `notes` as the header
    /// notes ("" = spec_to_json of the spec), the sculpt thread's `marks` and the menu's track `menu` (JSON text, ""
    /// = none: RecordingHeader::menu), the further workpieces' marks `more_marks` (recorded_marks), and frees the temporary file. Throws
    /// tridex::Error "<path>: ..." when the temporary file could not be written (a full disk: the error it met),
    /// read back, or the recording not written.
    /// `poses`: the loop's pose sets (RecordingHeader::poses).
    void finish(const std::string& notes, std::span<const SculptMark> marks, const std::string& menu = "",
                std::span<const std::vector<SculptMark>> more_marks = {},
                std::span<const haptics::PoseChange> poses = {});
    /// The recording file.
    const std::string& path() const { return path_; }

private:
    void drain();

    SessionSpec spec_;
    std::string path_;
    ToolOp op_;
    SpscRing<haptics::TickRecord> ring_{kRingTicks};
    std::FILE* tmp_ = nullptr;
    std::thread thread_;
    std::atomic<bool> running_{false};
    std::atomic<std::size_t> ticks_{0};
    std::string error_;  // the drain thread's first write error; read after stop()
};

}  // namespace tridex::app
