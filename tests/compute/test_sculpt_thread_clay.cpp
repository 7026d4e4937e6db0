// The sculpt thread with clay: a push stroke's haptic surface stays the stroke's start (Popescu 3.3's undeformed
// reference) and becomes the deformed surface when the stroke ends; undo of a push and smooth stroke restores exactly.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "compute/mesh/scan_convert.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/primitives.hpp"

namespace tridex::app {
namespace {

compute::TriDexel box_model() {
    const Aabb box{Vec3(-0.05), Vec3(0.05)};
    compute::TriDexel m = compute::TriDexel::empty(compute::Lattice::around(box, 48), std::size_t(1) << 30);
    compute::scan_convert(box_mesh(box), m);
    return m;
}

// Presses a 7 mm ball into the +z face at (0, 0), 3 mm deep over 300 ms, with `op`.
std::vector<ToolSample> press(ToolOp op) {
    std::vector<ToolSample> s(300);
    for (int i = 0; i < 300; ++i) {
        s[i].t_s = i * 1e-3;
        s[i].position = Vec3(0.0002 * i / 300.0, 0.0, 0.05 + 0.007 - 0.003 * (i + 1) / 300.0);
        s[i].tool.radius_m = 0.007;
        s[i].op = op;
    }
    return s;
}

// The lowest top (largest exit depth is the top of the +z face) over the Z window's rays: the dent's floor.
float lowest_top(const ActiveSurface& a) {
    const ActiveSurface::Window& w = a.sets[2];
    float lowest = 1e30f;
    for (int iv = 0; iv < w.nv; ++iv)
        for (int iu = 0; iu < w.nu; ++iu) {
            const int n = w.intervals(iu, iv);
            if (n > 0) lowest = std::min(lowest, w.exit(iu, iv, n - 1));
        }
    return lowest;
}

void wait_passes(const SculptThread& t) {
    const std::uint64_t p = t.passes();
    while (t.passes() < p + 2) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

TEST(SculptThreadClay, PushStrokeFeelsItsStartUntilItEnds) {
    compute::TriDexel m = box_model();
    const compute::TriDexel start = m;
    compute::Contourer contourer(m);
    contourer.update(m);
    SpscRing<ToolSample> ring(1024);
    TripleBuffer<ActiveSurface> surface;
    SculptThread t(m, contourer, ring, surface, Vec3(0.0, 0.0, 0.05));
    const float face = lowest_top(surface.latest());
    for (const ToolSample& s : press(ToolOp::kPush)) ASSERT_TRUE(ring.try_push(s));
    t.start();
    wait_passes(t);
    // The model is dented, the haptic surface is still the face.
    const float held = lowest_top(surface.latest());
    EXPECT_EQ(held, face);
    EXPECT_GT(t.stats().rays_changed, 0u);
    ASSERT_TRUE(t.request(SculptRequest::kEndStroke));
    wait_passes(t);
    const float after = lowest_top(surface.latest());
    EXPECT_LT(after, face - 0.5f);  // the stroke ended: the deformed surface is the new reference (plastic)
    std::printf("push reference: face at %.3f cells, held %.3f during the stroke, %.3f after it\n", face, held, after);
    // Undo restores the model exactly.
    ASSERT_TRUE(t.request(SculptRequest::kUndo));
    wait_passes(t);
    t.stop();
    for (int a = 0; a < 3; ++a)
        for (std::size_t r = 0; r < m.sets[a].rays.size(); ++r) {
            const auto& x = m.sets[a].rays[r];
            const auto& y = start.sets[a].rays[r];
            ASSERT_EQ(x.size(), y.size());
            for (std::size_t k = 0; k < x.size(); ++k) {
                ASSERT_EQ(x[k].enter, y[k].enter);
                ASSERT_EQ(x[k].exit, y[k].exit);
            }
        }
    EXPECT_EQ(lowest_top(surface.latest()), face);
}

TEST(SculptThreadClay, SmoothStrokePublishesAsItGoes) {
    compute::TriDexel m = box_model();
    compute::Contourer contourer(m);
    contourer.update(m);
    SpscRing<ToolSample> ring(1024);
    TripleBuffer<ActiveSurface> surface;
    SculptThread t(m, contourer, ring, surface, Vec3(0.0, 0.0, 0.05));
    const std::uint64_t seq0 = surface.latest().sequence;
    // First a push (its stroke closes when the op changes), then smooth over the dent.
    for (const ToolSample& s : press(ToolOp::kPush)) ASSERT_TRUE(ring.try_push(s));
    std::vector<ToolSample> sm = press(ToolOp::kSmooth);
    for (std::size_t i = 0; i < sm.size(); ++i) {
        sm[i].t_s += 0.3;
        sm[i].position = Vec3(-0.01 + 0.02 * i / 300.0, 0.0, 0.05 + 0.007 - 0.0025);
        ASSERT_TRUE(ring.try_push(sm[i]));
    }
    t.start();
    t.stop();
    EXPECT_GT(surface.latest().sequence, seq0 + 1);
    EXPECT_GE(t.stats().history.strokes, 2u);
}

}  // namespace
}  // namespace tridex::app
