// The frame-time budget's ladder (app/session/frame_budget): the occlusion, the levels of detail and the render
// scale stepped down within `react` frames of running long and back up a step at a time after a window that fits,
// with a longer wait after each trial that failed; sculpting frames learn a step of their own; bad options refused
// by name.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "app/session/view/frame_budget.hpp"
#include "core/error.hpp"

namespace tridex {
namespace {

FrameBudgetOptions budget_options(double target_ms, double min_scale, int window, int react, double lod_px = 1.0) {
    FrameBudgetOptions o;
    o.target_ms = target_ms;
    o.min_scale = min_scale;
    o.coarse_lod_px = lod_px;
    o.window = window;
    o.react = react;
    return o;
}

// The frame-time budget without a render scale or coarser levels (offscreen, fullscreen, --min-render-scale 1, no
// levels): the occlusion at 2x2 while the frames fit, 4x4 once the newest `react` frames' median is over the target,
// a trial of 2x2 once a window at 4x4 is within 90 % of it, and a longer wait after each trial that failed.
TEST(FrameBudget, QuarterWhileFramesAreOverTheTargetThenHalfAgain) {
    using renderer::OcclusionResolution;
    FrameBudget b(budget_options(25.0, 1.0, 10, 5));
    ASSERT_EQ(b.ladder().size(), 2u);
    const auto window = [&](double ms) {
        for (int i = 0; i < 10; ++i) b.add(ms);
        EXPECT_DOUBLE_EQ(b.quality().scale, 1.0);
        EXPECT_DOUBLE_EQ(b.quality().lod_px, 1.0);
        return b.quality().occlusion;
    };
    EXPECT_EQ(b.quality().occlusion, OcclusionResolution::kHalf);
    for (int i = 0; i < 10; ++i) b.add(i % 5 % 2 ? 40.0 : 20.0);  // every 5 frames' median fits (3 of them at 20)
    EXPECT_EQ(b.quality().occlusion, OcclusionResolution::kHalf);
    for (int i = 0; i < 4; ++i) b.add(34.0);
    EXPECT_EQ(b.quality().occlusion, OcclusionResolution::kHalf);  // a choice holds for `react` frames
    b.add(34.0);
    EXPECT_EQ(b.quality().occlusion, OcclusionResolution::kQuarter);  // 5 frames over: down at once
    EXPECT_EQ(window(30.0), OcclusionResolution::kQuarter);           // over, and no step below: stays
    EXPECT_EQ(window(20.0), OcclusionResolution::kHalf);              // within 22.5 (90 % of 25): a trial of 2x2
    for (int i = 0; i < 5; ++i) b.add(27.0);
    EXPECT_EQ(b.quality().occlusion, OcclusionResolution::kQuarter);  // the trial went over: back at once, wait 2
    EXPECT_EQ(window(20.0), OcclusionResolution::kQuarter);
    EXPECT_EQ(window(20.0), OcclusionResolution::kHalf);
    EXPECT_EQ(window(27.0), OcclusionResolution::kQuarter);  // failed again: wait 4 windows
    for (int k = 0; k < 3; ++k) EXPECT_EQ(window(20.0), OcclusionResolution::kQuarter);
    EXPECT_EQ(window(20.0), OcclusionResolution::kHalf);
    EXPECT_EQ(window(24.0), OcclusionResolution::kHalf);  // this trial fits: 2x2 stays
    EXPECT_EQ(window(24.0), OcclusionResolution::kHalf);
    for (int i = 0; i < 5; ++i) b.add(26.0);
    EXPECT_EQ(b.quality().occlusion, OcclusionResolution::kQuarter);
    EXPECT_EQ(window(20.0), OcclusionResolution::kHalf);  // the wait was reset by the trial that held
    EXPECT_EQ(b.switches(), 8u);
    EXPECT_EQ(b.frames_half() + b.frames_quarter(), 145u);
    EXPECT_EQ(b.frames_scaled(), 0u);
    EXPECT_EQ(b.frames_coarse_lod(), 0u);
    b.add(std::nan(""));  // ignored
    b.add(-1.0);
    EXPECT_EQ(b.frames_half() + b.frames_quarter(), 145u);
    const nlohmann::json j = b.to_json();
    EXPECT_EQ(j.at("now").at("occlusion"), "half");
    EXPECT_DOUBLE_EQ(j.at("now").at("scale").get<double>(), 1.0);
    EXPECT_DOUBLE_EQ(j.at("now").at("lod_px").get<double>(), 1.0);
    EXPECT_EQ(j.at("switches"), 8);
    EXPECT_EQ(j.at("react"), 5);
    EXPECT_DOUBLE_EQ(j.at("target_ms").get<double>(), 25.0);
    EXPECT_EQ(j.at("ladder").size(), 2u);
    // No budget: always the finest step.
    FrameBudget none(budget_options(0.0, 0.5, 5, 5, 4.0));
    for (int i = 0; i < 50; ++i) none.add(100.0);
    EXPECT_EQ(none.quality().occlusion, OcclusionResolution::kHalf);
    EXPECT_DOUBLE_EQ(none.quality().scale, 1.0);
    EXPECT_DOUBLE_EQ(none.quality().lod_px, 1.0);
    EXPECT_EQ(none.switches(), 0u);
    EXPECT_THROW(FrameBudget(budget_options(-1.0, 1.0, 30, 10)), Error);
    EXPECT_THROW(FrameBudget(budget_options(std::nan(""), 1.0, 30, 10)), Error);
    EXPECT_THROW(FrameBudget(budget_options(25.0, 0.4, 30, 10)), Error);
    EXPECT_THROW(FrameBudget(budget_options(25.0, 1.1, 30, 10)), Error);
    EXPECT_THROW(FrameBudget(budget_options(25.0, std::nan(""), 30, 10)), Error);
    EXPECT_THROW(FrameBudget(budget_options(25.0, 1.0, 2, 2)), Error);
    EXPECT_THROW(FrameBudget(budget_options(25.0, 1.0, 30, 0)), Error);
    EXPECT_THROW(FrameBudget(budget_options(25.0, 1.0, 30, 31)), Error);
    EXPECT_THROW(FrameBudget(budget_options(25.0, 1.0, 30, 10, 0.5)), Error);
    EXPECT_THROW(FrameBudget(budget_options(25.0, 1.0, 30, 10, 9.0)), Error);
    EXPECT_THROW(FrameBudget(budget_options(25.0, 1.0, 30, 10, std::nan(""))), Error);
    try {
        FrameBudget(budget_options(25.0, 1.0, 30, 10, 0.5));
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("--max-lod-px"), std::string::npos) << e.what();
    }
}

// In a desk window with levels of detail the ladder goes on below the occlusion at 4x4: the levels at up to 2 pixels
// of error, then the render scale in steps of 1/8 down to the lowest allowed, back up a step at a time as frames fit;
// with the occlusion off only the levels' and the scale's steps count.
TEST(FrameBudget, LevelsAndRenderScaleStepDownAndBackUp) {
    using renderer::OcclusionResolution;
    FrameBudget b(budget_options(25.0, 0.7, 5, 5, 2.0));
    ASSERT_EQ(b.ladder().size(), 6u);  // 2x2 at 1, 4x4 at 1, 4x4 2 px at 1, 0.875, 0.75, 0.7
    EXPECT_DOUBLE_EQ(b.ladder()[1].lod_px, 1.0);
    EXPECT_DOUBLE_EQ(b.ladder()[2].lod_px, 2.0);
    EXPECT_DOUBLE_EQ(b.ladder()[2].scale, 1.0);
    EXPECT_DOUBLE_EQ(b.ladder()[3].scale, 0.875);
    EXPECT_DOUBLE_EQ(b.ladder()[5].scale, 0.7);
    EXPECT_DOUBLE_EQ(b.ladder()[5].lod_px, 2.0);
    const auto window = [&](double ms, bool ao = true) {
        for (int i = 0; i < 5; ++i) b.add(ms, ao);
        return b.quality();
    };
    EXPECT_EQ(window(30.0).occlusion, OcclusionResolution::kQuarter);
    EXPECT_DOUBLE_EQ(window(30.0).lod_px, 2.0);
    EXPECT_DOUBLE_EQ(b.quality().scale, 1.0);
    EXPECT_DOUBLE_EQ(window(30.0).scale, 0.875);
    EXPECT_DOUBLE_EQ(window(30.0).scale, 0.75);
    EXPECT_DOUBLE_EQ(window(30.0).scale, 0.7);
    EXPECT_DOUBLE_EQ(window(30.0).scale, 0.7);   // the lowest: stays
    EXPECT_DOUBLE_EQ(window(24.0).scale, 0.7);   // fits, but not within 90 %: stays
    EXPECT_DOUBLE_EQ(window(20.0).scale, 0.75);  // a trial of the step above
    EXPECT_DOUBLE_EQ(window(24.0).scale, 0.75);  // it held
    EXPECT_DOUBLE_EQ(window(20.0).scale, 0.875);
    EXPECT_DOUBLE_EQ(window(26.0).scale, 0.75);  // that trial failed: wait 2 windows
    EXPECT_DOUBLE_EQ(window(20.0).scale, 0.75);
    EXPECT_DOUBLE_EQ(window(20.0).scale, 0.875);
    EXPECT_DOUBLE_EQ(window(20.0).scale, 1.0);
    EXPECT_DOUBLE_EQ(b.quality().lod_px, 2.0);
    EXPECT_DOUBLE_EQ(window(20.0).lod_px, 1.0);
    EXPECT_EQ(b.quality().occlusion, OcclusionResolution::kQuarter);
    EXPECT_EQ(window(20.0).occlusion, OcclusionResolution::kHalf);
    // The occlusion off: the step to 4x4 would change nothing, so a window over the target coarsens the levels at
    // once, and coming back skips it too.
    EXPECT_DOUBLE_EQ(window(30.0, false).lod_px, 2.0);  // (the trial of 2x2 failed: wait 2 windows)
    EXPECT_DOUBLE_EQ(b.quality().scale, 1.0);
    EXPECT_DOUBLE_EQ(window(20.0, false).lod_px, 2.0);
    EXPECT_DOUBLE_EQ(window(20.0, false).lod_px, 1.0);
    EXPECT_EQ(b.quality().occlusion, OcclusionResolution::kHalf);
    EXPECT_GT(b.frames_scaled(), 0u);
    EXPECT_GT(b.frames_coarse_lod(), b.frames_scaled());
    EXPECT_EQ(b.frames_half() + b.frames_quarter(), 19u * 5u);  // every window's frames
    const nlohmann::json j = b.to_json();
    EXPECT_DOUBLE_EQ(j.at("min_scale").get<double>(), 0.7);
    EXPECT_DOUBLE_EQ(j.at("coarse_lod_px").get<double>(), 2.0);
    EXPECT_EQ(j.at("ladder").at(5).at("occlusion"), "quarter");
    EXPECT_DOUBLE_EQ(j.at("ladder").at(5).at("lod_px").get<double>(), 2.0);
    EXPECT_EQ(j.at("frames_scaled"), b.frames_scaled());
    EXPECT_EQ(j.at("frames_coarse_lod"), b.frames_coarse_lod());
}

// Overload is met within `react` frames, relief only after a whole window: a burst of slow frames steps down before
// the window ends, and a trial that is slow from its first frames returns without waiting for its window.
TEST(FrameBudget, StepsDownWithinReactFramesAndUpOnlyAfterAWindow) {
    FrameBudget b(budget_options(25.0, 0.75, 30, 10, 2.0));
    ASSERT_EQ(b.ladder().size(), 5u);  // 2x2, 4x4, 4x4 2 px, 0.875, 0.75
    for (int i = 0; i < 10; ++i) b.add(30.0);  // under 1.25 times the target: one step per `react` frames
    EXPECT_EQ(b.quality().occlusion, renderer::OcclusionResolution::kQuarter);
    for (int i = 0; i < 10; ++i) b.add(30.0);
    EXPECT_DOUBLE_EQ(b.quality().lod_px, 2.0);
    for (int i = 0; i < 20; ++i) b.add(30.0);
    EXPECT_DOUBLE_EQ(b.quality().scale, 0.75);  // four steps in 40 frames
    for (int i = 0; i < 29; ++i) b.add(10.0);
    EXPECT_DOUBLE_EQ(b.quality().scale, 0.75);  // relief needs a whole window
    b.add(10.0);
    EXPECT_DOUBLE_EQ(b.quality().scale, 0.875);  // the trial
    for (int i = 0; i < 10; ++i) b.add(30.0);
    EXPECT_DOUBLE_EQ(b.quality().scale, 0.75);  // slow from its start: back after 10 frames
    for (int i = 0; i < 30; ++i) b.add(10.0);
    EXPECT_DOUBLE_EQ(b.quality().scale, 0.75);  // and the next trial waits two windows
    for (int i = 0; i < 30; ++i) b.add(10.0);
    EXPECT_DOUBLE_EQ(b.quality().scale, 0.875);
    EXPECT_EQ(b.switches(), 7u);
}

// The further the frames run over the target, the more steps the budget takes at once: one below 1.25^2 times the
// target, two from there, three from 1.25^3 times, ..., so a heavy overload is not drawn for `react` frames per step.
TEST(FrameBudget, HeavyOverloadTakesSeveralStepsAtOnce) {
    struct Case {
        double frame_ms;
        std::size_t level;  // the step after the first `react` frames
    };
    // 2x2, 4x4, 4x4 2 px, 0.875, 0.75, 0.625, 0.5
    for (const Case c : {Case{30.0, 1}, Case{38.0, 1}, Case{40.0, 2}, Case{49.0, 3}, Case{62.0, 4}, Case{400.0, 6}}) {
        FrameBudget b(budget_options(25.0, 0.5, 30, 10, 2.0));
        ASSERT_EQ(b.ladder().size(), 7u);
        for (int i = 0; i < 9; ++i) b.add(c.frame_ms);
        EXPECT_DOUBLE_EQ(b.quality().scale, 1.0) << c.frame_ms;  // nothing before `react` frames
        b.add(c.frame_ms);
        const FrameQuality& want = b.ladder()[c.level];
        EXPECT_DOUBLE_EQ(b.quality().scale, want.scale) << c.frame_ms;
        EXPECT_DOUBLE_EQ(b.quality().lod_px, want.lod_px) << c.frame_ms;
        EXPECT_EQ(b.quality().occlusion, want.occlusion) << c.frame_ms;
        EXPECT_EQ(b.switches(), 1u) << c.frame_ms;  // one change, however many steps
    }
}

// Frames drawn while sculpting learn their own step: a stroke steps down, the calm frames after it draw at their own
// step at once, and the next stroke starts at the step the last one ended on instead of stepping down again.
TEST(FrameBudget, SculptingFramesKeepAStepOfTheirOwn) {
    FrameBudget b(budget_options(25.0, 0.75, 30, 10, 2.0));
    ASSERT_EQ(b.ladder().size(), 5u);  // 2x2, 4x4, 4x4 2 px, 0.875, 0.75
    for (int i = 0; i < 30; ++i) b.add(15.0);
    EXPECT_FALSE(b.sculpting());
    EXPECT_DOUBLE_EQ(b.sculpting_quality().scale, 1.0);  // nothing learnt: the calm step
    // The first stroke starts where the calm frames are and steps down while its frames run long.
    b.set_sculpting(true);
    EXPECT_TRUE(b.sculpting());
    EXPECT_EQ(b.quality().occlusion, renderer::OcclusionResolution::kHalf);
    for (int i = 0; i < 40; ++i) b.add(40.0);
    EXPECT_DOUBLE_EQ(b.quality().scale, 0.75);
    for (int i = 0; i < 20; ++i) b.add(24.0);  // fits, but not within 90 %: it stays
    // Between strokes: the calm frames' step, at once, untouched by the stroke.
    b.set_sculpting(false);
    EXPECT_EQ(b.quality().occlusion, renderer::OcclusionResolution::kHalf);
    EXPECT_DOUBLE_EQ(b.quality().scale, 1.0);
    EXPECT_DOUBLE_EQ(b.sculpting_quality().scale, 0.75);
    for (int i = 0; i < 60; ++i) b.add(15.0);
    EXPECT_DOUBLE_EQ(b.quality().scale, 1.0);
    // The next stroke starts at 0.75 with no slow frame drawn at a finer step.
    b.set_sculpting(true);
    EXPECT_DOUBLE_EQ(b.quality().scale, 0.75);
    EXPECT_DOUBLE_EQ(b.quality().lod_px, 2.0);
    b.set_sculpting(true);  // again: nothing changes
    EXPECT_DOUBLE_EQ(b.quality().scale, 0.75);
    for (int i = 0; i < 10; ++i) b.add(24.0);
    EXPECT_EQ(b.frames_sculpting(), 70u);
    const nlohmann::json j = b.to_json();
    EXPECT_EQ(j.at("frames_sculpting"), 70u);
    EXPECT_DOUBLE_EQ(j.at("now").at("scale").get<double>(), 0.75);
    EXPECT_DOUBLE_EQ(j.at("now_sculpting").at("scale").get<double>(), 0.75);
    EXPECT_DOUBLE_EQ(j.at("now_calm").at("scale").get<double>(), 1.0);
    EXPECT_EQ(j.at("now_calm").at("occlusion"), "half");
    // Frames are counted per step whichever kind they are.
    std::uint64_t all = 0;
    for (const std::uint64_t n : b.frames()) all += n;
    EXPECT_EQ(all, 30u + 60u + 60u + 10u);
}

}  // namespace
}  // namespace tridex
