// haptics/wrench_output.hpp - force + torque (a wrench) and its mapping to what a device can render.
#pragma once

#include "core/math.hpp"
#include "devices/haptic_device.hpp"

namespace tridex::haptics {

/// A force (N) and a torque (N*m) about a stated point (the tool centre for MultiPointRenderer).
struct Wrench {
    Vec3 force_n{0};
    Vec3 torque_nm{0};
};

/// Actuated degrees of freedom of a device's output.
enum class OutputDof {
    k3,  ///< force only (PHANTOM Omni)
    k5,  ///< force + torque about device x and z; the roll axis (device y, the wand's axis) is not actuated
    k6,  ///< force + torque about every axis
};

/// What a device can render, device frame: per-axis and magnitude limits (0 on an axis = not actuated).
struct OutputLimits {
    OutputDof dof = OutputDof::k3;
    Vec3 max_force_axis_n{0.0};    ///< |F_x|, |F_y|, |F_z| limits, N
    double max_force_n = 0.0;      ///< |F| limit, N
    Vec3 max_torque_axis_nm{0.0};  ///< |tau_x|, |tau_y|, |tau_z| limits, N*m
    double max_torque_nm = 0.0;    ///< |tau| limit, N*m
};

/// The output limits of a device profile: dof from profile.dof_out (3 -> k3, 5 -> k5, 6 -> k6), per-axis
/// limits from devices::axis_limits (the Quanser wand: 2.3/2.1/3.0 N, 0.230/0/0.250 N*m, Singapogu ch. 3),
/// magnitudes from max_force_n / max_torque_nm; k3 gets zero torque limits. Throws tridex::Error naming
/// DeviceProfile.dof_out when it is not 3, 5 or 6, or the limit field when a limit is negative or not finite.
OutputLimits output_limits(const devices::DeviceProfile& profile);

/// Maps a world-frame wrench to the device frame and to what the device can render:
/// 1. rotate force and torque by world_to_device (unit quaternion);
/// 2. drop what is not actuated: all torque for k3, the roll (device y) torque for k5, and any component
///    whose axis limit is 0;
/// 3. scale force and torque each by one factor s = min(1, max/|v|, min_i limit_i/|v_i|), so both stay within
///    every per-axis limit and the magnitude limit while keeping their direction (no per-axis clipping,
///    which would turn the force).
/// Returns a zero wrench when anything is non-finite (wrench, quaternion or limits); a negative limit
/// counts as 0. Allocation-free, for the haptic loop.
Wrench map_to_device(const Wrench& world, const Quat& world_to_device, const OutputLimits& limits);

}  // namespace tridex::haptics
