// Tests of FrameSequencer: eye alternation at the display rate, swap eyes, the emitter hook.
#include <gtest/gtest.h>

#include <limits>
#include <thread>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "renderer/output/frame_sequencer.hpp"

namespace tridex::renderer {
namespace {

TEST(FrameSequencer, AlternatesEyesStartingWithTheLeft) {
    FrameSequencer seq(120.0);
    for (std::uint64_t n = 0; n < 10; ++n) {
        EXPECT_EQ(seq.shutter_for_present(n), static_cast<int>(n % 2));
        EXPECT_EQ(seq.eye_for_present(n), static_cast<int>(n % 2));
    }
    EXPECT_EQ(seq.eye_for_present(std::numeric_limits<std::uint64_t>::max()), 1);
}

TEST(FrameSequencer, SwapEyesFlipsTheImageButNotTheShutter) {
    FrameSequencer seq(120.0, true);
    EXPECT_TRUE(seq.swap_eyes());
    EXPECT_EQ(seq.eye_for_present(0), 1);
    EXPECT_EQ(seq.shutter_for_present(0), 0);
    seq.set_swap_eyes(false);
    EXPECT_EQ(seq.eye_for_present(0), 0);
    // Swapping from another thread (the input thread) is seen by the presenting thread.
    std::thread other([&] { seq.set_swap_eyes(true); });
    other.join();
    EXPECT_EQ(seq.eye_for_present(3), 0);
}

TEST(FrameSequencer, PresentReportsEveryShutterToTheEmitterHook) {
    FrameSequencer seq(120.0);
    std::vector<std::pair<int, std::uint64_t>> emitter;
    seq.on_eye([&](int eye, std::uint64_t present) { emitter.emplace_back(eye, present); });
    std::vector<int> shown;
    for (int i = 0; i < 4; ++i) shown.push_back(seq.present());
    seq.set_swap_eyes(true);
    for (int i = 0; i < 2; ++i) shown.push_back(seq.present());
    EXPECT_EQ(seq.presents(), 6u);
    EXPECT_EQ(shown, (std::vector<int>{0, 1, 0, 1, 1, 0}));
    ASSERT_EQ(emitter.size(), 6u);
    for (std::uint64_t n = 0; n < 6; ++n) {
        EXPECT_EQ(emitter[n].first, static_cast<int>(n % 2));  // the shutter keeps alternating L, R
        EXPECT_EQ(emitter[n].second, n);
    }
}

TEST(FrameSequencer, TimingAtTheDisplayRate) {
    FrameSequencer seq(120.0);
    EXPECT_DOUBLE_EQ(seq.refresh_hz(), 120.0);
    EXPECT_DOUBLE_EQ(seq.per_eye_hz(), 60.0);
    EXPECT_DOUBLE_EQ(seq.present_time_s(120), 1.0);
    EXPECT_DOUBLE_EQ(seq.present_time_s(3), 0.025);
    for (std::uint64_t n : {0ull, 1ull, 3ull, 7ull, 119ull, 120ull, 12345ull})
        EXPECT_EQ(seq.present_at(seq.present_time_s(n)), n);
    EXPECT_EQ(seq.present_at(0.0125), 1u);  // 1.5 presents in
    EXPECT_THROW(seq.present_at(-0.001), Error);
    EXPECT_THROW(seq.present_at(std::numeric_limits<double>::quiet_NaN()), Error);
}

// Injected missed presents: a present shown one refresh late (timing) or three late (a frame counter) flips the
// shutter phase; the sequencer counts the misses and shows each later present on the eye whose shutter is open.
TEST(FrameSequencer, KeepsTheEyeOrderAfterMissedPresents) {
    FrameSequencer seq(120.0);
    std::vector<std::pair<int, int>> hooked;  // (shutter, present) as the emitter hook saw them
    seq.on_eye([&](int eye, std::uint64_t n) { hooked.emplace_back(eye, static_cast<int>(n)); });
    const double T = 1.0 / 120.0, t0 = 1000.0;
    // Presents 0..3 on refreshes 0..3 (jitter of a quarter refresh is no miss).
    for (int n = 0; n < 4; ++n) {
        EXPECT_EQ(seq.present(), n % 2);
        EXPECT_TRUE(seq.presented(t0 + n * T + (n == 2 ? 0.25 * T : 0.0)));
    }
    EXPECT_EQ(seq.missed_refreshes(), 0u);
    // Present 4 (expected on refresh 4, left) is shown on refresh 5: one refresh missed.
    EXPECT_EQ(seq.present(), 0);
    EXPECT_TRUE(seq.presented(t0 + 5 * T));
    EXPECT_EQ(seq.missed_refreshes(), 1u);
    EXPECT_EQ(seq.late_presents(), 1u);
    // The next refresh is 6: the left shutter again. Alternating per present would show the right eye.
    EXPECT_EQ(seq.next_shutter(), 0);
    EXPECT_EQ(seq.present(), 0);
    EXPECT_TRUE(seq.presented(t0 + 6 * T));
    EXPECT_EQ(seq.present(), 1);  // refresh 7: right
    EXPECT_TRUE(seq.presented(t0 + 7 * T));
    EXPECT_EQ(seq.missed_refreshes(), 1u);
    // Every present went to the shutter of its refresh (the late one excepted: it was chosen for refresh 4).
    const std::vector<std::pair<int, int>> want = {{0, 0}, {1, 1}, {0, 2}, {1, 3}, {0, 4}, {0, 5}, {1, 6}};
    EXPECT_EQ(hooked, want);
    EXPECT_EQ(seq.shown_shutters() & 0x7Fu, 0b0101001u);  // oldest first: 0 1 0 1 0 0 1
    // Swap eyes flips the image, not the shutter.
    seq.set_swap_eyes(true);
    EXPECT_EQ(seq.next_shutter(), 0);
    EXPECT_EQ(seq.next_eye(), 1);
    seq.set_swap_eyes(false);
    // Decreasing or non-finite times are ignored.
    EXPECT_FALSE(seq.presented(t0));
    EXPECT_FALSE(seq.presented(std::numeric_limits<double>::quiet_NaN()));

    // A display frame counter: three refreshes missed before present 2 (odd: the phase flips).
    FrameSequencer counted(120.0);
    EXPECT_EQ(counted.present(), 0);
    EXPECT_TRUE(counted.presented_at_refresh(500));
    EXPECT_EQ(counted.present(), 1);
    EXPECT_TRUE(counted.presented_at_refresh(501));
    EXPECT_EQ(counted.present(), 0);
    EXPECT_TRUE(counted.presented_at_refresh(505));  // expected 502
    EXPECT_EQ(counted.missed_refreshes(), 3u);
    EXPECT_EQ(counted.present(), 0);  // refresh 506 = 6 after the first: left
    EXPECT_TRUE(counted.presented_at_refresh(506));
    EXPECT_EQ(counted.present(), 1);
    EXPECT_FALSE(counted.presented_at_refresh(506));  // a counter that does not move is ignored
}

TEST(FrameSequencer, BadRateIsRefused) {
    EXPECT_THROW(FrameSequencer(0.0), Error);
    EXPECT_THROW(FrameSequencer(-60.0), Error);
    EXPECT_THROW(FrameSequencer(1001.0), Error);
    EXPECT_THROW(FrameSequencer(std::numeric_limits<double>::infinity()), Error);
}

}  // namespace
}  // namespace tridex::renderer
