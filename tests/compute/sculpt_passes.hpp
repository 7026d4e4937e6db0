// tests/compute/sculpt_passes.hpp - tool samples for sculpt-thread tests on the 48-cell box (box_model(48, 6.5,
// 41.5)): passes across its +z face, pushed into the thread's ring, and a wait for the thread to take them.
#pragma once

#include <chrono>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "compute/runtime/sculpt_thread.hpp"
#include "sweep_programs.hpp"

namespace tridex::app::test {

/// A pass along x over the 48-cell box's +z face at height y, `n` samples from t0_s at 1 kHz, a 4 mm ball tool
/// with `op` and material 2.
inline std::vector<ToolSample> pass(double y, double t0_s, int n, ToolOp op) {
    std::vector<ToolSample> s(static_cast<std::size_t>(n));
    const compute::TriDexel m = compute::test::box_model(48, 6.5, 41.5);
    const Vec3 top = m.lattice.to_world(Vec3(24.0, 24.0, 41.5));
    for (int i = 0; i < n; ++i) {
        const double u = i / (n - 1.0);
        s[static_cast<std::size_t>(i)].t_s = t0_s + i * 1e-3;
        s[static_cast<std::size_t>(i)].position = top + Vec3(-0.015 + 0.03 * u, y, -0.002);
        s[static_cast<std::size_t>(i)].tool.radius_m = 0.004;
        s[static_cast<std::size_t>(i)].op = op;
        s[static_cast<std::size_t>(i)].material = 2;
    }
    return s;
}

/// Pushes every sample, yielding while the ring is full.
inline void push_all(SpscRing<ToolSample>& ring, const std::vector<ToolSample>& s) {
    for (const ToolSample& x : s)
        while (!ring.try_push(x)) std::this_thread::yield();
}

/// Waits until every sample pushed and every request queued so far has taken effect: the ring is empty and two more
/// passes of the thread's loop finished (the first may have begun before; the second began after). Fails the test
/// after a minute instead of hanging.
inline void wait_drained(const SpscRing<ToolSample>& ring, const SculptThread& t) {
    const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (ring.size() > 0 && std::chrono::steady_clock::now() < limit)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const std::uint64_t k = t.passes();
    while (t.passes() < k + 2 && std::chrono::steady_clock::now() < limit)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (std::chrono::steady_clock::now() >= limit) ADD_FAILURE() << "the sculpt thread did not settle within 60 s";
}

}  // namespace tridex::app::test
