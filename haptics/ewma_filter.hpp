// haptics/ewma_filter.hpp - exponentially weighted moving average of the rendered force.
#pragma once

#include "core/math.hpp"

namespace tridex::haptics {

/// Force smoothing filter F_i = (1 - a) * E_i + a * F_{i-1}, with F_{-1} = 0 after construction or
/// reset(): a unit step input gives exactly 1 - a^n after n samples (up to rounding).
/// Source: Peng et al., "Haptic Interface Technique in Large-Scale Virtual Environment" (force filter,
/// a = 0.9 at 1 kHz, i.e. a time constant of about 9.5 ticks).
class EwmaFilter {
public:
    /// alpha: weight a of the previous output, in [0, 1); 0 passes the input through.
    /// Throws tridex::Error ("ewma_alpha ...") when alpha is outside [0, 1) or not finite.
    explicit EwmaFilter(double alpha = 0.9);

    /// Feeds one sample E_i (any unit, usually N) and returns F_i. Allocation-free.
    Vec3 apply(const Vec3& sample) {
        out_ = (1.0 - alpha_) * sample + alpha_ * out_;
        return out_;
    }
    /// The last output F_{i-1} (zero after reset).
    const Vec3& value() const { return out_; }
    /// Forgets the history: the next output is (1 - a) * E.
    void reset() { out_ = Vec3(0.0); }
    /// The weight a.
    double alpha() const { return alpha_; }

private:
    double alpha_;
    Vec3 out_{0.0};
};

}  // namespace tridex::haptics
