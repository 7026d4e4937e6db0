// app/session/frame_loop.cpp - the one frame loop (frame_loop.hpp).
#include "app/session/frame_loop.hpp"

#include <chrono>
#include <thread>

namespace tridex::app {

std::uint64_t run_frames(FrameSteps& steps, const FramePacing& pacing) {
    using Clock = std::chrono::steady_clock;
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
