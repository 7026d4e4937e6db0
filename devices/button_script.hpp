// devices/button_script.hpp - timed button presses and releases for a scripted device.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tridex::devices {

/// One step of a button script: from device time t_s (s) on, the buttons are `bits` (bit i = button i).
struct ButtonStep {
    double t_s = 0.0;         ///< device time the bits take effect, s
    std::uint32_t bits = 0u;  ///< button bits from t_s until the next step
};

/// A piecewise-constant button signal in device time: bits_at(t) is the bits of the last step with
/// t_s <= t, and 0 (no button) before the first step or for an empty script. So a press of button 0
/// from 1 s to 2 s is {{1.0, 1u}, {2.0, 0u}}. Lets a scripted stroke press and release buttons
/// deterministically, whatever the wall-clock timing. Evaluation is O(log n), allocation-free and safe
/// from the haptic thread.
class ButtonScript {
public:
    /// An empty script: no button is ever pressed.
    ButtonScript() = default;
    /// Steps with finite, strictly increasing times (s); any bits. Throws tridex::Error naming the index
    /// ("ButtonScript: steps[i].t_s ...") when a time is not finite or does not increase.
    explicit ButtonScript(std::vector<ButtonStep> steps);

    /// The button bits at device time t_s (s); 0 before the first step. A NaN time gives 0.
    std::uint32_t bits_at(double t_s) const;
    /// The steps, in time order.
    const std::vector<ButtonStep>& steps() const { return steps_; }
    /// Number of steps.
    std::size_t size() const { return steps_.size(); }
    /// True when there are no steps.
    bool empty() const { return steps_.empty(); }

private:
    std::vector<ButtonStep> steps_;
};

}  // namespace tridex::devices
