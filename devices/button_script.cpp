// devices/button_script.cpp - validation and lookup of timed button steps.
#include "devices/button_script.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tridex::devices {

ButtonScript::ButtonScript(std::vector<ButtonStep> steps) : steps_(std::move(steps)) {
    for (std::size_t i = 0; i < steps_.size(); ++i) {
        const std::string where = "ButtonScript: steps[" + std::to_string(i) + "].t_s = " + std::to_string(steps_[i].t_s);
        if (!std::isfinite(steps_[i].t_s)) throw Error(where + " is not finite");
        if (i > 0 && !(steps_[i].t_s > steps_[i - 1].t_s))
            throw Error(where + " does not increase (previous " + std::to_string(steps_[i - 1].t_s) + ")");
    }
}

std::uint32_t ButtonScript::bits_at(double t_s) const {
    if (steps_.empty() || !(t_s >= steps_.front().t_s)) return 0u;  // also catches NaN
    // The last step with t <= t_s: one before the first step strictly after t_s.
    const auto it = std::upper_bound(steps_.begin(), steps_.end(), t_s,
                                     [](double t, const ButtonStep& s) { return t < s.t_s; });
    return std::prev(it)->bits;
}

}  // namespace tridex::devices
