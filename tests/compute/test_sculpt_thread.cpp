// The sculpt thread: the model is a pure function of the tool-sample stream, and failures surface.
#include <gtest/gtest.h>

#include <chrono>
#include <limits>
#include <thread>

#include "compute/runtime/sculpt_thread.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"
#include "journal_stream.hpp"

namespace tridex::app {
namespace {

compute::TriDexel box_model() { return test::box_model(48); }

// A wavy carving path across the box's +z face, 400 samples.
std::vector<ToolSample> stream() { return test::wavy_cut(400); }

// Runs the stream through a SculptThread; `trickle` pushes it sample by sample while the thread runs
// (the batching then depends on timing), otherwise all samples are queued before the thread starts.
compute::TriDexel sculpt(bool trickle, SculptStats* stats = nullptr) {
    compute::TriDexel m = box_model();
    compute::Contourer contourer(m);
    contourer.update(m);
    SpscRing<ToolSample> ring(1024);
    TripleBuffer<ActiveSurface> surface;
    SculptThread t(m, contourer, ring, surface, Vec3(0.0));
    // The first snapshot holds no sample: every sample the haptic loop makes is newer.
    EXPECT_EQ(surface.latest().applied_made_s, -std::numeric_limits<double>::infinity());
    const auto samples = stream();
    if (!trickle) {
        for (const auto& s : samples) EXPECT_TRUE(ring.try_push(s));
    }
    t.start();
    if (trickle) {
        for (std::size_t i = 0; i < samples.size(); ++i) {
            while (!ring.try_push(samples[i])) std::this_thread::yield();
            if (i % 7 == 0) std::this_thread::sleep_for(std::chrono::microseconds(300));
        }
    }
    t.stop();
    if (stats) *stats = t.stats();
    EXPECT_GT(surface.latest().sequence, 1u);  // snapshots were published after the changes
    // Each says which samples it holds: the made_s of the newest one applied.
    EXPECT_GE(surface.latest().applied_made_s, 100.0);
    EXPECT_LE(surface.latest().applied_made_s, 499.0);
    return m;
}

TEST(SculptThread, SameStreamGivesTheSameDexelsWhateverTheBatching) {
    SculptStats sa, sb;
    const compute::TriDexel a = sculpt(false, &sa);
    const compute::TriDexel b = sculpt(true, &sb);
    EXPECT_EQ(sa.booleans, 399u);
    EXPECT_EQ(sb.booleans, 399u);
    EXPECT_GT(sa.rays_changed, 0u);
    std::size_t compared = 0;
    for (int k = 0; k < 3; ++k) {
        ASSERT_EQ(a.sets[k].rays.size(), b.sets[k].rays.size());
        for (std::size_t r = 0; r < a.sets[k].rays.size(); ++r) {
            const auto& x = a.sets[k].rays[r];
            const auto& y = b.sets[k].rays[r];
            ASSERT_EQ(x.size(), y.size()) << "set " << k << " ray " << r;
            for (std::size_t n = 0; n < x.size(); ++n) {
                EXPECT_EQ(x[n].enter, y[n].enter);
                EXPECT_EQ(x[n].exit, y[n].exit);
                ++compared;
            }
        }
    }
    EXPECT_GT(compared, 1000u);
}

TEST(SculptThread, AFailureOnTheThreadIsRethrownByStopAndTheRingStaysDrained) {
    compute::TriDexel m = box_model();
    compute::Contourer contourer(m);
    SpscRing<ToolSample> ring(16);
    TripleBuffer<ActiveSurface> surface;
    SculptThread t(m, contourer, ring, surface, Vec3(0.0));
    ToolSample s;
    s.op = ToolOp::kSubtract;
    s.tool.radius_m = 0.005;
    ASSERT_TRUE(ring.try_push(s));
    s.position = Vec3(std::numeric_limits<double>::quiet_NaN());  // a corrupt sample: subtract_capsule throws
    ASSERT_TRUE(ring.try_push(s));
    t.start();
    for (int i = 0; i < 64; ++i)  // more than the ring holds: the failed thread must keep draining
        while (!ring.try_push(s)) std::this_thread::yield();
    EXPECT_THROW(t.stop(), Error);
    EXPECT_NO_THROW(t.stop());  // idempotent
    EXPECT_THROW(SculptThread(m, contourer, ring, surface, Vec3(std::numeric_limits<double>::infinity())), Error);
}

}  // namespace
}  // namespace tridex::app
