// app/session/frame_loop.cpp - the one frame loop (frame_loop.hpp).
#include "app/session/frame_loop.hpp"

#include <chrono>
#include <thread>

#include "core/cpu_reservation.hpp"

namespace tridex::app {

std::uint64_t run_frames(FrameSteps& steps, const FramePacing& pacing) {
    using Clock = std::chrono::steady_clock;
    // The thread that draws presents too: a software present writes the whole frame to the display server in
    // one system call, which would delay the haptic loop's start on its CPU (core/cpu_reservation.hpp).
    const KeepOffReservedCpu off_the_haptic_cpu;
    const Clock::time_point t0 = Clock::now();
    for (std::uint64_t frame = 0;; ++frame) {
        if (!steps.take_input()) return frame;
        const bool last = steps.last_frame(frame);
        steps.draw(frame);
        if (last) return frame + 1;
        if (pacing.sleep && pacing.period_s > 0.0)
            std::this_thread::sleep_until(t0 + std::chrono::duration_cast<Clock::duration>(
                                                   std::chrono::duration<double>(static_cast<double>(frame + 1) *
                                                                                 pacing.period_s)));
    }
}

}  // namespace tridex::app
