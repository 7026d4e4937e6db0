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

TEST(FrameSequencer, BadRateIsRefused) {
    EXPECT_THROW(FrameSequencer(0.0), Error);
    EXPECT_THROW(FrameSequencer(-60.0), Error);
    EXPECT_THROW(FrameSequencer(1001.0), Error);
    EXPECT_THROW(FrameSequencer(std::numeric_limits<double>::infinity()), Error);
}

}  // namespace
}  // namespace tridex::renderer
