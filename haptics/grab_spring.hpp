// haptics/grab_spring.hpp - what the hand feels while it grabs (ToolOp::kGrab): a spring to the point where the grab
// gripped the material.
#pragma once

#include "core/math.hpp"

namespace tridex::haptics {

/// Default stiffness of the grab spring, N/m (world): a tenth of an Omni-class wall (0.7 N/mm), so a 3.3 N device
/// saturates after a 47 mm drag and the spring stays far inside the passivity bound at 1 kHz.
inline constexpr double kGrabStiffnessNPerM = 70.0;

/// Checks a grab spring's stiffness k (N/m: finite and >= 0, else throws tridex::Error
/// "HapticLoopConfig.grab_stiffness_n_per_m ...") and caps it at cap_n_per_m when that is > 0 (the device's stiffness
/// limit). Returns true when it capped k.
bool cap_grab_stiffness(double& k, double cap_n_per_m);

/// The grab's spring (a Freeform-style tug): while a grab is engaged, the hand is pulled back toward the anchor, the
/// HIP where the grab gripped: F = -k (hip - anchor), world N (the caller clamps it to the device's force limit, as
/// every force of the loop). It grips on the first engaged tick the tool touches material (the sculpt thread's grab
/// grips where the ball touches, compute/tools/clay_grab.hpp) and lets go when the grab is no longer engaged (button
/// up, another op, the menu open, the tool decoupled). Popescu, Burdea, Bouzit, section 3.3 (the elastic part of a
/// deformation felt as a spring). Allocation-free, never throws (the haptic thread runs it).
class GrabSpring {
public:
    /// k: stiffness, N/m (finite, >= 0; the loop caps it at the device's stiffness limit).
    explicit GrabSpring(double stiffness_n_per_m = kGrabStiffnessNPerM) : k_(stiffness_n_per_m) {}

    /// One tick: `grabbing` whether a grab is engaged this tick, `touching` whether the tool touches material, hip_m
    /// the HIP (world m). Returns the spring force (world N; 0 when not gripping or hip_m is not finite).
    Vec3 update(bool grabbing, bool touching, const Vec3& hip_m);

    /// True while gripping (between the grip and the release).
    bool gripping() const { return gripping_; }
    /// The anchor (world m); meaningful while gripping().
    const Vec3& anchor_m() const { return anchor_m_; }
    /// Stiffness, N/m.
    double stiffness_n_per_m() const { return k_; }

private:
    double k_;
    bool gripping_ = false;
    Vec3 anchor_m_{0.0};
};

}  // namespace tridex::haptics
