// app/input/wand_navigation.cpp - the Wand's grab, scale and reset.
#include "app/input/wand_navigation.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace tridex::app {
namespace {

bool held(std::uint64_t buttons, int b) { return b >= 0 && ((buttons >> b) & 1u) != 0; }

bool usable(const Pose& p) {
    const Quat& q = p.orientation;
    const double n = glm::length(q);
    return is_finite(p.position) && std::isfinite(n) && n > 0.0;
}

}  // namespace

WandNavigator::WandNavigator(const WandNavigationSettings& s) : settings_(s) {
    const auto button_ok = [](int b) { return b >= -1 && b < 64; };
    if (!button_ok(s.grab_button) || !button_ok(s.reset_button) || (s.grab_button >= 0 && s.grab_button == s.reset_button))
        throw Error("wand: the grab and reset buttons must be different indices in 0..63 (or -1: none)");
    if (!std::isfinite(s.scale_rate_per_s) || s.scale_rate_per_s < 0.0)
        throw Error("wand: scale_rate_per_s must be finite and >= 0 (ln of the factor per s)");
    if (!(s.dead_zone >= 0.0 && s.dead_zone < 1.0)) throw Error("wand: dead_zone must be in [0, 1)");
    if (!std::isfinite(s.max_dt_s) || s.max_dt_s < 0.0) throw Error("wand: max_dt_s must be finite and >= 0 (s)");
    if (!is_finite(s.pivot_m)) throw Error("wand: the pivot must be finite (m)");
}

void WandNavigator::update(const WandSample& s, double dt_s, renderer::SceneNavigation& nav) {
    if (!s.fresh || !usable(s.pose) || !std::isfinite(s.joystick_y)) {
        ++frames_lost_;
        if (grabbing_) ++grabs_dropped_;
        grabbing_ = false;
        return;
    }
    ++frames_tracked_;
    const std::uint64_t pressed = s.buttons & ~prev_buttons_;
    prev_buttons_ = s.buttons;
    if (held(pressed, settings_.reset_button)) {
        nav.reset();
        ++resets_;
        grabbing_ = false;
        return;
    }
    if (held(s.buttons, settings_.grab_button)) {
        if (grabbing_) {
            nav.wand_drag(anchor_, s.pose);
        } else {
            grabbing_ = true;
            ++grabs_;
        }
        anchor_ = s.pose;
    } else {
        grabbing_ = false;
    }
    const double y = std::clamp(s.joystick_y, -1.0, 1.0);
    const double dt = std::isfinite(dt_s) ? std::clamp(dt_s, 0.0, settings_.max_dt_s) : 0.0;
    if (settings_.joystick_scales && std::abs(y) > settings_.dead_zone && dt > 0.0)
        scaled_by_ *= nav.scale(std::exp(settings_.scale_rate_per_s * y * dt), settings_.pivot_m);
}

}  // namespace tridex::app
