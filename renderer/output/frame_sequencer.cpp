// renderer/output/frame_sequencer.cpp - eye alternation, swap and emitter hook of frame-sequential stereo.
#include "renderer/output/frame_sequencer.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tridex::renderer {

FrameSequencer::FrameSequencer(double refresh_hz, bool swap_eyes) : refresh_hz_(refresh_hz), swap_eyes_(swap_eyes) {
    if (!std::isfinite(refresh_hz) || !(refresh_hz > 0.0) || refresh_hz > 1000.0)
        throw Error("FrameSequencer: refresh_hz must be in (0, 1000] Hz (got " + std::to_string(refresh_hz) + ")");
}

int FrameSequencer::shutter_for_present(std::uint64_t n) const { return static_cast<int>(n & 1u); }

int FrameSequencer::eye_for_present(std::uint64_t n) const {
    return shutter_for_present(n) ^ (swap_eyes_.load(std::memory_order_relaxed) ? 1 : 0);
}

void FrameSequencer::set_swap_eyes(bool swap) { swap_eyes_.store(swap, std::memory_order_relaxed); }

bool FrameSequencer::swap_eyes() const { return swap_eyes_.load(std::memory_order_relaxed); }

void FrameSequencer::on_eye(std::function<void(int eye, std::uint64_t present)> hook) { hook_ = std::move(hook); }

int FrameSequencer::present() {
    const std::uint64_t n = presents_++;
    const int eye = eye_for_present(n);
    if (hook_) hook_(shutter_for_present(n), n);
    return eye;
}

std::uint64_t FrameSequencer::presents() const { return presents_; }

double FrameSequencer::refresh_hz() const { return refresh_hz_; }

double FrameSequencer::per_eye_hz() const { return 0.5 * refresh_hz_; }

double FrameSequencer::present_time_s(std::uint64_t n) const { return static_cast<double>(n) / refresh_hz_; }

std::uint64_t FrameSequencer::present_at(double t_s) const {
    if (!std::isfinite(t_s) || t_s < 0.0)
        throw Error("FrameSequencer::present_at: t_s must be finite and >= 0 (got " + std::to_string(t_s) + ")");
    return static_cast<std::uint64_t>(std::floor(t_s * refresh_hz_ + 1e-9));
}

}  // namespace tridex::renderer
