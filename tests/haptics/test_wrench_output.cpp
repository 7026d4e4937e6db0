// Tests of haptics/wrench_output and devices/device_profiles: 3-DOF drops torque, the 5-DOF wand drops the
// roll torque and clamps to 2.3/2.1/3.0 N and 230/250 N*mm (Singapogu ch. 3), 6-DOF, non-finite -> zero.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "devices/device_profiles.hpp"
#include "haptics/tool_points.hpp"
#include "haptics/wrench_output.hpp"

namespace tridex::haptics {
namespace {

const Quat kIdentity(1, 0, 0, 0);

void expect_vec(const Vec3& a, const Vec3& b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

TEST(DeviceProfiles, WandAndGeneric6Dof) {
    const devices::DeviceProfile w = devices::quanser_wand_5dof();
    EXPECT_EQ(w.dof_in, 5);
    EXPECT_EQ(w.dof_out, 5);
    EXPECT_NEAR(w.max_force_n, std::sqrt(2.3 * 2.3 + 2.1 * 2.1 + 3.0 * 3.0), 1e-12);  // 4.330 N
    EXPECT_NEAR(w.max_torque_nm, std::sqrt(0.23 * 0.23 + 0.25 * 0.25), 1e-12);        // 0.340 N*m
    const devices::AxisLimits a = devices::axis_limits(w);
    expect_vec(a.max_force_n, Vec3(2.3, 2.1, 3.0), 0.0);
    expect_vec(a.max_torque_nm, Vec3(0.230, 0.0, 0.250), 0.0);
    const devices::DeviceProfile g = devices::generic_6dof();
    EXPECT_EQ(g.dof_out, 6);
    expect_vec(devices::axis_limits(g).max_torque_nm, Vec3(0.3), 0.0);
    // Any other 5-DOF profile: torque on x and z only; a 3-DOF profile: none.
    devices::DeviceProfile five = g;
    five.dof_out = 5;
    expect_vec(devices::axis_limits(five).max_torque_nm, Vec3(0.3, 0.0, 0.3), 0.0);
    expect_vec(devices::axis_limits(devices::DeviceProfile::phantom_omni()).max_torque_nm, Vec3(0.0), 0.0);
    expect_vec(devices::axis_limits(devices::DeviceProfile::phantom_omni()).max_force_n, Vec3(0.88), 0.0);
    devices::DeviceProfile bad = g;
    bad.max_torque_nm = -1.0;
    EXPECT_THROW(devices::axis_limits(bad), Error);
    // Per-axis fields decide, not the name: a renamed wand keeps its limits, and any profile can set them.
    devices::DeviceProfile renamed = w;
    renamed.name = "my wand";
    expect_vec(devices::axis_limits(renamed).max_force_n, Vec3(2.3, 2.1, 3.0), 0.0);
    expect_vec(devices::axis_limits(renamed).max_torque_nm, Vec3(0.230, 0.0, 0.250), 0.0);
    devices::DeviceProfile custom = g;
    custom.max_force_axis_n = Vec3(1.0, 2.0, 3.0);
    expect_vec(devices::axis_limits(custom).max_force_n, Vec3(1.0, 2.0, 3.0), 0.0);
    expect_vec(devices::axis_limits(custom).max_torque_nm, Vec3(0.3), 0.0);
    custom.max_torque_axis_nm = Vec3(0.1, std::nan(""), 0.1);
    try {
        devices::axis_limits(custom);
        ADD_FAILURE() << "a NaN per-axis torque limit was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("max_torque_axis_nm[1]"), std::string::npos) << e.what();
    }
}

TEST(WrenchOutput, LimitsFromProfiles) {
    const OutputLimits omni = output_limits(devices::DeviceProfile::phantom_omni());
    EXPECT_EQ(omni.dof, OutputDof::k3);
    EXPECT_EQ(omni.max_force_n, 0.88);
    EXPECT_EQ(omni.max_torque_nm, 0.0);
    expect_vec(omni.max_torque_axis_nm, Vec3(0.0), 0.0);
    const OutputLimits wand = output_limits(devices::quanser_wand_5dof());
    EXPECT_EQ(wand.dof, OutputDof::k5);
    expect_vec(wand.max_force_axis_n, Vec3(2.3, 2.1, 3.0), 0.0);
    expect_vec(wand.max_torque_axis_nm, Vec3(0.230, 0.0, 0.250), 0.0);
    EXPECT_EQ(output_limits(devices::generic_6dof()).dof, OutputDof::k6);
    devices::DeviceProfile odd = devices::generic_6dof();
    odd.dof_out = 4;
    EXPECT_THROW(output_limits(odd), Error);
    odd.dof_out = 6;
    odd.max_force_n = NAN;
    EXPECT_THROW(output_limits(odd), Error);
}

TEST(WrenchOutput, ThreeDofDropsTorque) {
    const OutputLimits omni = output_limits(devices::DeviceProfile::phantom_omni());
    const Wrench d = map_to_device({Vec3(0.1, -0.2, 0.3), Vec3(1, 2, 3)}, kIdentity, omni);
    expect_vec(d.force_n, Vec3(0.1, -0.2, 0.3), 0.0);
    expect_vec(d.torque_nm, Vec3(0.0), 0.0);
    // |F| = 1.76 N > 0.88 N: scaled by one half, direction kept.
    expect_vec(map_to_device({Vec3(1.056, -1.408, 0), Vec3(0.0)}, kIdentity, omni).force_n,
               Vec3(0.528, -0.704, 0), 1e-15);
}

TEST(WrenchOutput, FiveDofDropsRollTorqueAndClampsPerAxis) {
    const OutputLimits wand = output_limits(devices::quanser_wand_5dof());
    // Within limits: only the roll (y) torque goes.
    Wrench d = map_to_device({Vec3(1.0, -1.0, 2.0), Vec3(0.1, 0.2, -0.05)}, kIdentity, wand);
    expect_vec(d.force_n, Vec3(1.0, -1.0, 2.0), 0.0);
    expect_vec(d.torque_nm, Vec3(0.1, 0.0, -0.05), 0.0);
    // Each axis alone clamps to its own limit.
    expect_vec(map_to_device({Vec3(10, 0, 0), Vec3(0.0)}, kIdentity, wand).force_n, Vec3(2.3, 0, 0), 1e-15);
    expect_vec(map_to_device({Vec3(0, -10, 0), Vec3(0.0)}, kIdentity, wand).force_n, Vec3(0, -2.1, 0), 1e-15);
    expect_vec(map_to_device({Vec3(0, 0, 10), Vec3(0.0)}, kIdentity, wand).force_n, Vec3(0, 0, 3.0), 1e-15);
    expect_vec(map_to_device({Vec3(0.0), Vec3(1, 0, 0)}, kIdentity, wand).torque_nm, Vec3(0.230, 0, 0), 1e-15);
    expect_vec(map_to_device({Vec3(0.0), Vec3(0, 0, -1)}, kIdentity, wand).torque_nm, Vec3(0, 0, -0.250), 1e-15);
    // Mixed: one factor for all axes keeps the direction (x binds: 2.3/4.6 = 0.5).
    expect_vec(map_to_device({Vec3(4.6, 2.1, 0), Vec3(0.0)}, kIdentity, wand).force_n, Vec3(2.3, 1.05, 0), 1e-15);
    expect_vec(map_to_device({Vec3(0.0), Vec3(0.5, 7.0, 0.5)}, kIdentity, wand).torque_nm, Vec3(0.23, 0, 0.23),
               1e-15);
    // k5 drops the roll torque even when a hand-made OutputLimits gives that axis a limit.
    const OutputLimits loose{OutputDof::k5, Vec3(10.0), 10.0, Vec3(1.0), 1.0};
    expect_vec(map_to_device({Vec3(0.0), Vec3(0.1, 0.2, 0.3)}, kIdentity, loose).torque_nm, Vec3(0.1, 0, 0.3), 0.0);
    // The device frame matters: a world torque about x, with the device turned 90 deg about z, is about
    // device y (the roll axis) and is dropped; a world force along y is along device -x and clamps to 2.3 N.
    const Quat turn = rotation_from_axis_angle(Vec3(0, 0, 1), std::numbers::pi / 2);
    d = map_to_device({Vec3(0, 10, 0), Vec3(0.2, 0, 0)}, turn, wand);
    expect_vec(d.force_n, Vec3(-2.3, 0, 0), 1e-12);
    expect_vec(d.torque_nm, Vec3(0.0), 1e-12);
}

TEST(WrenchOutput, SixDofClampsMagnitude) {
    const OutputLimits g = output_limits(devices::generic_6dof());
    // |(3, 4, 0)| = 5 > 3 N and the y axis (4 > 3): the magnitude binds (3/5 = 0.6 < 3/4).
    const Wrench d = map_to_device({Vec3(3, 4, 0), Vec3(0, 0.1, -0.2)}, kIdentity, g);
    expect_vec(d.force_n, Vec3(1.8, 2.4, 0), 1e-15);
    expect_vec(d.torque_nm, Vec3(0, 0.1, -0.2), 0.0);  // roll torque kept on 6-DOF
}

TEST(WrenchOutput, NonFiniteGivesZero) {
    const OutputLimits wand = output_limits(devices::quanser_wand_5dof());
    const Wrench ok{Vec3(1, 1, 1), Vec3(0.1, 0, 0.1)};
    Wrench w = ok;
    w.force_n.y = NAN;
    Wrench d = map_to_device(w, kIdentity, wand);
    expect_vec(d.force_n, Vec3(0.0), 0.0);
    expect_vec(d.torque_nm, Vec3(0.0), 0.0);
    w = ok;
    w.torque_nm.z = INFINITY;
    d = map_to_device(w, kIdentity, wand);
    expect_vec(d.force_n, Vec3(0.0), 0.0);
    expect_vec(d.torque_nm, Vec3(0.0), 0.0);
    d = map_to_device(ok, Quat(NAN, 0, 0, 0), wand);
    expect_vec(d.force_n, Vec3(0.0), 0.0);
    OutputLimits bad = wand;
    bad.max_force_n = INFINITY;
    expect_vec(map_to_device(ok, kIdentity, bad).force_n, Vec3(0.0), 0.0);
    // The finite wrench goes through unchanged (within limits).
    d = map_to_device(ok, kIdentity, wand);
    expect_vec(d.force_n, ok.force_n, 0.0);
    expect_vec(d.torque_nm, ok.torque_nm, 0.0);
}

}  // namespace
}  // namespace tridex::haptics
