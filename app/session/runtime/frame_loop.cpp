// app/session/runtime/frame_loop.cpp - the one frame loop (frame_loop.hpp).
#include "app/session/runtime/frame_loop.hpp"

#include <algorithm>
#include <chrono>
#include <string>
#include <thread>

#include "core/cpu_reservation.hpp"
#include "core/error.hpp"

namespace tridex::app {

std::uint64_t run_frames(FrameSteps& steps, const FramePacing& pacing) {
    using Clock = std::chrono::steady_clock;
    if (!(pacing.early_gap_s >= 0.0) || (pacing.sleep && pacing.early_gap_s > pacing.period_s))
        throw Error("run_frames: early_gap_s must lie in 0..period_s (" + std::to_string(pacing.period_s) + "), got " +
                    std::to_string(pacing.early_gap_s));
    const auto seconds = [](double s) {
        return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
    };
    // The thread that draws presents too: a software present writes the whole frame to the display server in
    // one system call, which would delay the haptic loop's start on its CPU (core/cpu_reservation.hpp).
    const KeepOffReservedCpu off_the_haptic_cpu;
    Clock::time_point anchor = Clock::now();  // frames start at anchor + k * period_s, k = 0, 1, ...
    std::uint64_t since_anchor = 0;
    for (std::uint64_t frame = 0;; ++frame) {
        const Clock::time_point start = Clock::now();
        if (!steps.take_input()) return frame;
        const bool last = steps.last_frame(frame);
        steps.draw(frame);
        if (last) return frame + 1;
        if (!pacing.sleep || pacing.period_s <= 0.0) continue;
        const Clock::time_point next = anchor + seconds(static_cast<double>(since_anchor + 1) * pacing.period_s);
        bool early = false;
        if (pacing.early_gap_s > 0.0) {
            std::this_thread::sleep_until(std::min(next, start + seconds(pacing.early_gap_s)));
            early = Clock::now() < next && steps.wait_for_news(next);
        } else {
            std::this_thread::sleep_until(next);
        }
        const Clock::time_point now = Clock::now();
        if (early || now >= next + seconds(pacing.period_s)) {  // early, or a whole period late: count from now
            anchor = now;
            since_anchor = 0;
        } else {
            ++since_anchor;
        }
    }
}

}  // namespace tridex::app
