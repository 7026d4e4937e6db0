// renderer/output/frame_sequencer.cpp - eye alternation, swap and emitter hook of frame-sequential stereo.
#include "renderer/output/frame_sequencer.hpp"

#include <algorithm>
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

int FrameSequencer::next_shutter() const { return static_cast<int>(next_refresh_ & 1u); }

int FrameSequencer::next_eye() const { return next_shutter() ^ (swap_eyes_.load(std::memory_order_relaxed) ? 1 : 0); }

int FrameSequencer::present() {
    const std::uint64_t n = presents_++;
    const int shutter = next_shutter();
    const int eye = next_eye();
    if (hook_) hook_(shutter, n);
    history_ = (history_ << 1) | static_cast<std::uint64_t>(shutter);
    last_refresh_ = next_refresh_++;
    return eye;
}

void FrameSequencer::shown_late(std::uint64_t extra) {
    if (extra == 0) return;
    missed_ += extra;
    ++late_;
    last_refresh_ += extra;
    next_refresh_ = last_refresh_ + 1;
}

bool FrameSequencer::presented(double t_s) {
    if (!std::isfinite(t_s) || (have_t_ && t_s < last_t_s_)) return false;
    if (!have_t_) {
        have_t_ = true;
        first_t_s_ = t_s;
        first_refresh_ = last_refresh_;
    } else {
        // The refresh the display is at, from the time since the first present shown (no drift from summing
        // intervals); later than the refresh this present was expected on = shown late.
        const double at = std::round((t_s - first_t_s_) * refresh_hz_) + static_cast<double>(first_refresh_);
        if (at > static_cast<double>(last_refresh_) && at < 1e18)
            shown_late(static_cast<std::uint64_t>(at) - last_refresh_);
    }
    last_t_s_ = t_s;
    return true;
}

bool FrameSequencer::presented_at_refresh(std::uint64_t refresh) {
    if (have_counter_ && refresh <= last_counter_) return false;
    if (have_counter_) shown_late(refresh - last_counter_ - 1);
    have_counter_ = true;
    last_counter_ = refresh;
    return true;
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
