// tests/haptics/loop_fixture.hpp - helpers for running the haptic loop against a simulated device.
#pragma once

#include <chrono>
#include <thread>

#include "core/active_surface.hpp"
#include "core/triple_buffer.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::test {

/// Publishes a copy of `s` as the newest snapshot of `buffer`.
inline void publish(TripleBuffer<ActiveSurface>& buffer, const ActiveSurface& s) {
    buffer.back() = s;
    buffer.publish();
}

/// Waits up to timeout_s for the loop to end by itself; true when it did.
inline bool wait_until_stopped(const haptics::HapticLoop& loop, double timeout_s) {
    const auto t0 = std::chrono::steady_clock::now();
    while (loop.running()) {
        if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > timeout_s) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return true;
}

}  // namespace tridex::test
