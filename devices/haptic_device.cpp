// devices/haptic_device.cpp - the device profiles and the interface's out-of-line destructor.
#include "devices/haptic_device.hpp"

#include "core/units.hpp"

namespace tridex::devices {

HapticDevice::~HapticDevice() = default;

DeviceProfile DeviceProfile::phantom_omni() {
    DeviceProfile p;
    p.name = "PHANTOM Omni";
    const Vec3 half = 0.5 * Vec3(units::inch(6.4), units::inch(4.8), units::inch(2.8));
    p.workspace_m = Aabb{-half, half};
    p.max_force_n = 0.88;
    p.max_torque_nm = 0.0;
    p.max_stiffness_n_per_m = units::n_per_mm(0.7);
    p.dof_in = 6;
    p.dof_out = 3;
    return p;
}

}  // namespace tridex::devices
