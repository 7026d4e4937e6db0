// The one frame loop (app/session/runtime/frame_loop.hpp): frames on the period's grid, news starting a frame early but not
// before the gap, a late frame not made up, and a gap longer than the period refused. The checks are lower bounds on
// when frames start (a sleep never ends early, so a frame never starts before its place on the grid or the gap) and
// totals with wide margins, so a busy machine cannot fail them. A frame that starts late may be followed sooner than a
// period by the next, which keeps its place on the grid.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <thread>
#include <vector>

#include "app/session/runtime/frame_loop.hpp"
#include "core/error.hpp"

namespace tridex::app {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_between(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

// Draws `frames` frames, recording when each started; news (when `news`) is always there; frame `slow` (if any)
// takes `slow_s` to draw.
struct Recorder final : FrameSteps {
    std::uint64_t frames = 10;
    bool news = false;
    std::uint64_t slow = UINT64_MAX;
    double slow_s = 0.0;
    std::vector<Clock::time_point> starts;
    std::uint64_t early = 0;

    bool take_input() override {
        starts.push_back(Clock::now());
        return true;
    }
    bool last_frame(std::uint64_t frame) override { return frame + 1 >= frames; }
    void draw(std::uint64_t frame) override {
        if (frame == slow) std::this_thread::sleep_for(std::chrono::duration<double>(slow_s));
    }
    bool wait_for_news(Clock::time_point deadline) override {
        if (news) {
            ++early;
            return true;
        }
        return FrameSteps::wait_for_news(deadline);
    }
    // Seconds from frame k's start to frame k + 1's.
    double interval(std::size_t k) const { return seconds_between(starts[k], starts[k + 1]); }
    // Whether every frame from `from` on started no sooner than its place on a grid of `period_s` from frame `from`
    // (within 5 ms: frame `from` itself starts a moment after the loop fixed the grid, longer on a busy machine).
    bool on_or_after_grid(std::size_t from, double period_s) const {
        for (std::size_t k = from + 1; k < starts.size(); ++k)
            if (seconds_between(starts[from], starts[k]) < static_cast<double>(k - from) * period_s - 5e-3)
                return false;
        return true;
    }
};

constexpr double kPeriodS = 0.04;
constexpr double kGapS = 0.02;

TEST(FrameLoop, FramesKeepThePeriodWithoutNews) {
    Recorder steps;
    EXPECT_EQ(run_frames(steps, FramePacing{kPeriodS, true, kGapS}), 10u);
    ASSERT_EQ(steps.starts.size(), 10u);
    EXPECT_EQ(steps.early, 0u);
    EXPECT_TRUE(steps.on_or_after_grid(0, kPeriodS));
}

TEST(FrameLoop, NewsStartsAFrameEarlyButNotBeforeTheGap) {
    Recorder steps;
    steps.news = true;
    EXPECT_EQ(run_frames(steps, FramePacing{kPeriodS, true, kGapS}), 10u);
    EXPECT_EQ(steps.early, 9u);  // every frame after the first started on news
    for (std::size_t k = 0; k + 1 < steps.starts.size(); ++k) EXPECT_GE(steps.interval(k), kGapS) << k;
    // Nine intervals at the gap, against nine periods without news.
    EXPECT_LT(seconds_between(steps.starts.front(), steps.starts.back()), 9 * kPeriodS - 0.05);
    // Without an early gap the same news changes nothing.
    Recorder fixed;
    fixed.news = true;
    run_frames(fixed, FramePacing{kPeriodS, true});
    EXPECT_EQ(fixed.early, 0u);
    EXPECT_TRUE(fixed.on_or_after_grid(0, kPeriodS));
}

TEST(FrameLoop, ALateFrameIsNotMadeUp) {
    Recorder steps;
    steps.slow = 3;
    steps.slow_s = 3.5 * kPeriodS;  // frames 4 to 6 would have started by then
    run_frames(steps, FramePacing{kPeriodS, true});
    ASSERT_EQ(steps.starts.size(), 10u);
    // The frame after the late one starts at once, and the ones after it on a grid from it again, not in a burst.
    EXPECT_GE(steps.interval(3), steps.slow_s);
    EXPECT_TRUE(steps.on_or_after_grid(4, kPeriodS));
}

TEST(FrameLoop, AGapLongerThanThePeriodIsRefused) {
    Recorder steps;
    EXPECT_THROW(run_frames(steps, FramePacing{kPeriodS, true, 2 * kPeriodS}), Error);
    EXPECT_THROW(run_frames(steps, FramePacing{kPeriodS, true, -1.0}), Error);
    EXPECT_TRUE(steps.starts.empty());  // refused before the first frame
}

}  // namespace
}  // namespace tridex::app
