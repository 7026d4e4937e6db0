// devices/device_profiles.hpp - more device profiles (5-DOF wand, generic 6-DOF) and per-axis output limits.
#pragma once

#include "core/math.hpp"
#include "devices/haptic_device.hpp"

namespace tridex::devices {

/// Quanser 5-DOF Haptic Wand as used in Singapogu's MS thesis (Clemson 2007), ch. 3: continuous force
/// limits 2.3 N (x), 2.1 N (y), 3.0 N (z) and torque limits 230 N*mm and 250 N*mm about the two actuated
/// rotation axes; the roll about the wand's own axis is neither actuated nor sensed (dof_in = dof_out = 5).
/// Device-frame convention (an assumption: the thesis gives the numbers, not our frame): the wand lies
/// along device y in its home pose, so the torque axes are x (0.230 N*m) and z (0.250 N*m) and y is the
/// unactuated roll axis. Since DeviceProfile holds one force and one torque limit, max_force_n is the
/// magnitude with every axis at its limit, |(2.3, 2.1, 3.0)| = 4.33 N, and max_torque_nm =
/// |(0.230, 0.250)| = 0.340 N*m: loose bounds; the per-axis fields max_force_axis_n = (2.3, 2.1, 3.0) N and
/// max_torque_axis_nm = (0.230, 0, 0.250) N*m are the real ones.
/// workspace_m: the thesis's Table 1 workspace about the wand's calibration point (the device origin):
/// x in [-240, 240] mm, y in [85, 335] mm, z in [-215, 235] mm; so the box is not centred on the origin
/// (home_position_m() gives its centre, (0, 210, 10) mm). rotation_range_rad is left unset: no source
/// at hand gives the wand's rotation range. max_stiffness_n_per_m (700 N/m, as the Omni) is an
/// assumption, not from the thesis.
DeviceProfile quanser_wand_5dof();

/// A neutral 6-DOF profile for simulation and tests, not a specific product: 0.2 m cube workspace centred
/// on the device origin, 3.0 N and 0.3 N*m continuous limits on every axis and in magnitude, 1000 N/m
/// stable stiffness, 6-DOF sensing and output.
DeviceProfile generic_6dof();

/// Novint Falcon (3-DOF delta haptic device, USB; driven by devices/falcon/). Novint's published figures: a 4 x 4 x 4
/// inch (0.1 m) workspace, force capabilities over 2 lbf (8.9 N), position resolution over 400 dpi. Device frame:
/// libnifalcon's (devices/falcon/falcon_kinematics.hpp: x right, y up, z toward the user, origin at the base).
/// workspace_m: the 80 mm cube x, y in [-0.04, 0.04], z in [0.075, 0.155] m around the grip's rest position
/// (0, 0, 0.115): the corners of a 4-inch cube are out of the legs' reach, this cube is reachable with a
/// well-conditioned Jacobian everywhere (checked in tests/devices/test_falcon_kinematics.cpp). max_force_n = 8.9 N
/// (the published "over 2 lbf"; a peak figure: no continuous rating is published). max_stiffness_n_per_m = 1000 N/m is
/// an assumption (no stiffness is published). Position sensing only (dof_in = 3), force output (dof_out = 3).
DeviceProfile novint_falcon();

/// Where a device's stylus rests at home, device frame, m: the centre of profile.workspace_m (the device
/// origin for an empty box). A scripted hand's path and the workspace mapping are placed around it, so a
/// device whose workspace is not centred on its origin (the Quanser wand) starts inside its workspace.
/// A tracked stick or rigid body held in a PowerWall room, with no actuators (the "tracked" profile of the
/// flystick and tracked-body drivers): its workspace is the tracked volume in front of the screen in the wall
/// frame (the display config's tracker_to_wall; screen at z = 0, viewer at +z, y up), x -3..3 m, y -0.5..3 m,
/// z -1..4 m; 6-DOF sensing; the loop's 3-DOF force path with limits of 0 N and 0 N m, so no force is sent.
DeviceProfile tracked_tool_profile();

Vec3 home_position_m(const DeviceProfile& profile);

/// Per-axis continuous limits in the device frame (N, N*m); 0 on an axis = that axis is not actuated.
struct AxisLimits {
    Vec3 max_force_n{0.0};    ///< |F_x|, |F_y|, |F_z| limits, N
    Vec3 max_torque_nm{0.0};  ///< |tau_x|, |tau_y|, |tau_z| limits, N*m
};

/// The per-axis limits of a profile: its max_force_axis_n / max_torque_axis_nm when set (the Quanser wand sets
/// both); otherwise its scalar force limit on every axis and its scalar torque limit on every axis for
/// dof_out >= 6, on x and z only for dof_out == 5 (y = the roll axis, as the wand), on none for dof_out < 5.
/// Throws tridex::Error naming the profile and field when a limit is negative or not finite.
AxisLimits axis_limits(const DeviceProfile& profile);

}  // namespace tridex::devices
