// app/session/runtime/frame_loop.hpp - the one frame loop every session is driven by: input, the end of the session, and
// the frame drawn through the session's sink, at the display's rate.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <thread>
#include <utility>

namespace tridex::app {

/// The steps of one frame of a session, called in order by run_frames. A session implements them once; a window,
/// fullscreen, the wall and offscreen differ only in the stereo sink draw() sends the frame to, and a session whose
/// picture is rendered once from the final model (demo, replay: the end-only offscreen sink) draws nothing per frame.
class FrameSteps {
public:
    virtual ~FrameSteps() = default;
    /// This frame's input: window events, scripted keys, the device's main-thread poll (HapticDevice::
    /// poll_on_main_thread). Returns false when the person ended the session (Esc, the window closed): the loop
    /// then ends without drawing this frame.
    virtual bool take_input() = 0;
    /// Whether frame `frame` (0-based) is the session's last; it is still drawn. The implementation records why.
    virtual bool last_frame(std::uint64_t frame) = 0;
    /// Draws frame `frame` through the session's sink (or nothing, for the end-only sink).
    virtual void draw(std::uint64_t frame) = 0;
    /// Between frames, when the pacing lets a frame start early (FramePacing::early_gap_s): waits until the
    /// session has something to draw that the last frame did not (a sculpted change published since) and returns
    /// true, or returns false at `deadline`. The default has nothing to wait for: it sleeps until `deadline`.
    virtual bool wait_for_news(std::chrono::steady_clock::time_point deadline) {
        std::this_thread::sleep_until(deadline);
        return false;
    }
};

/// FrameSteps from three callables, for a session whose frames need no class of their own (a device-time
/// simulation stepping its haptic loop once a frame, a server polling its state).
struct FrameFunctions final : FrameSteps {
    std::function<bool()> input;                 ///< take_input()
    std::function<bool(std::uint64_t)> last;     ///< last_frame(frame)
    std::function<void(std::uint64_t)> frame;    ///< draw(frame)

    FrameFunctions(std::function<bool()> i, std::function<bool(std::uint64_t)> l, std::function<void(std::uint64_t)> f)
        : input(std::move(i)), last(std::move(l)), frame(std::move(f)) {}
    bool take_input() override { return input(); }
    bool last_frame(std::uint64_t f) override { return last(f); }
    void draw(std::uint64_t f) override { frame(f); }
};

/// How run_frames paces frames.
struct FramePacing {
    /// Seconds from one frame's start to the next's (> 0 when `sleep`); the display's refresh period times its
    /// presents per frame, or the end-only sink's polling period.
    double period_s = 1.0 / 60.0;
    /// Sleep until the next frame's start: offscreen and end-only sinks (a window's present waits for the display
    /// instead; a device-time simulation runs as fast as it computes).
    bool sleep = true;
    /// With `sleep`, s (0 <= early_gap_s <= period_s): when > 0, a frame starts before its time as soon as the
    /// steps have news (FrameSteps::wait_for_news), but not sooner than early_gap_s after the last frame's start,
    /// and the frames after it keep the period from there, like a display with a variable refresh rate. 0: frames
    /// start only on the period's grid.
    double early_gap_s = 0.0;
};

/// Drives `steps` frame by frame on the calling thread (a window's events and GLFW need the main thread) until
/// take_input() returns false or the frame last_frame() named has been drawn. When pacing sleeps, frames start
/// period_s apart (a frame that starts a whole period late or more starts at once and the period counts from it,
/// so missed frames are not made up; with early_gap_s, news starts a frame early). While it runs, the calling
/// thread stays off the CPU a real-time haptic loop holds (KeepOffReservedCpu, core/cpu_reservation.hpp). Returns
/// the frames drawn. Throws tridex::Error when early_gap_s lies outside 0..period_s; exceptions from the steps
/// propagate.
std::uint64_t run_frames(FrameSteps& steps, const FramePacing& pacing);

}  // namespace tridex::app
