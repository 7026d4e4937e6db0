// devices/haptic_device.hpp - the abstract haptic device: what it can do, one sample, read and write.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/aabb.hpp"
#include "core/math.hpp"
#include "core/pose.hpp"

namespace tridex::devices {

/// What a haptic device can do, in SI units and in the device frame.
struct DeviceProfile {
    std::string name;                    ///< human-readable model name
    Aabb workspace_m;                    ///< reachable box of the stylus tip in the device frame, m
    double max_force_n = 0.0;            ///< continuous force limit, N (the loop clamps |F| to it)
    double max_torque_nm = 0.0;          ///< continuous torque limit, N*m; 0 for 3-DOF output
    double max_stiffness_n_per_m = 0.0;  ///< highest virtual-wall stiffness that stays stable at 1 kHz, N/m
    int dof_in = 0;                      ///< sensed degrees of freedom (6 = position + orientation)
    int dof_out = 0;                     ///< actuated degrees of freedom (3 = force only)
    /// Per-axis continuous force limits in the device frame, N (|F_x|, |F_y|, |F_z|); unset = max_force_n on
    /// every axis. devices::axis_limits() reads it.
    std::optional<Vec3> max_force_axis_n;
    /// Per-axis continuous torque limits in the device frame, N*m; 0 on an axis = not actuated; unset =
    /// derived from max_torque_nm and dof_out (devices::axis_limits()).
    std::optional<Vec3> max_torque_axis_nm;
    /// Per-axis range of the stylus orientation about its home orientation, rad: |angle| <= limit about
    /// device x, y, z (e.g. the wand's pitch and yaw); unset = not known, no limit is modelled.
    std::optional<Vec3> rotation_range_rad;

    /// SensAble (3D Systems) PHANTOM Omni, from its published specification sheet:
    /// workspace 160 x 120 x 70 mm (6.4 x 4.8 x 2.8 in, width x height x depth = device x, y, z),
    /// here centred on the device origin; max_force_n = 0.88 N, the sheet's "continuous exertable
    /// force (24 h)" (the 3.3 N "maximum exertable force at nominal position" is a peak the motors
    /// cannot hold, so it is not used as the safety limit); max_stiffness_n_per_m = 700 N/m
    /// (0.7 N/mm, DESIGN.md; the sheet lists 1.02 N/mm on its weakest axis, z, so 0.7 keeps a margin);
    /// 6-DOF sensing, 3-DOF force output, no torque.
    static DeviceProfile phantom_omni();
};

/// One sample from the device, in the device frame.
struct DeviceState {
    double t_s = 0.0;            ///< device time, s
    Pose pose;                   ///< stylus pose: tip position (m) and orientation (unit quaternion)
    Vec3 velocity_m_s{0.0};      ///< tip velocity, m/s
    std::uint32_t buttons = 0;   ///< button bits, bit i = button i pressed
};

/// Abstract haptic device (CHAI3D/HAPI style: one interface for hardware, simulated and replayed devices).
/// read() returns false when the device has vanished (unplugged, end of a replay); the caller then
/// commands zero force and stops. write() sends force (N) and torque (N*m), both in the device frame.
/// Implementations are driven from one thread (the haptic loop); read() and write() must not allocate,
/// lock or block for longer than a fraction of the loop period.
class HapticDevice {
public:
    virtual ~HapticDevice();
    /// The device's capabilities; constant for the device's lifetime.
    virtual const DeviceProfile& profile() const = 0;
    /// Fetches the newest sample into out. Returns false (out unspecified) when the device is gone.
    virtual bool read(DeviceState& out) = 0;
    /// Commands force_n (N) and torque_nm (N*m) in the device frame until the next write.
    virtual void write(const Vec3& force_n, const Vec3& torque_nm) = 0;
};

}  // namespace tridex::devices
