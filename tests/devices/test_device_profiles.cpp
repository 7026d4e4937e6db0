// Tests of devices/device_profiles: the Quanser wand's thesis workspace (not centred on the device
// origin), the home position inside every profile's workspace, and the optional rotation range.
#include <gtest/gtest.h>

#include "devices/device_profiles.hpp"

namespace tridex::devices {
namespace {

bool inside(const Aabb& box, const Vec3& p) {
    return p.x >= box.lo.x && p.x <= box.hi.x && p.y >= box.lo.y && p.y <= box.hi.y && p.z >= box.lo.z &&
           p.z <= box.hi.z;
}

TEST(DeviceProfiles, QuanserWandWorkspaceIsTheThesisTable) {
    const DeviceProfile w = quanser_wand_5dof();
    // Singapogu (2007) Table 1, mm about the calibration point.
    EXPECT_DOUBLE_EQ(w.workspace_m.lo.x, -0.240);
    EXPECT_DOUBLE_EQ(w.workspace_m.hi.x, 0.240);
    EXPECT_DOUBLE_EQ(w.workspace_m.lo.y, 0.085);
    EXPECT_DOUBLE_EQ(w.workspace_m.hi.y, 0.335);
    EXPECT_DOUBLE_EQ(w.workspace_m.lo.z, -0.215);
    EXPECT_DOUBLE_EQ(w.workspace_m.hi.z, 0.235);
    EXPECT_FALSE(inside(w.workspace_m, Vec3(0.0)));  // the calibration point is outside the box
    const Vec3 home = home_position_m(w);
    EXPECT_NEAR(home.x, 0.0, 1e-15);
    EXPECT_NEAR(home.y, 0.210, 1e-15);
    EXPECT_NEAR(home.z, 0.010, 1e-15);
    EXPECT_FALSE(w.rotation_range_rad.has_value());  // no source gives it: left unset
}

TEST(DeviceProfiles, HomeIsInsideEveryWorkspace) {
    for (const DeviceProfile& p : {DeviceProfile::phantom_omni(), quanser_wand_5dof(), generic_6dof()})
        EXPECT_TRUE(inside(p.workspace_m, home_position_m(p))) << p.name;
    // Centred workspaces keep their home exactly at the origin.
    EXPECT_EQ(home_position_m(DeviceProfile::phantom_omni()), Vec3(0.0));
    EXPECT_EQ(home_position_m(generic_6dof()), Vec3(0.0));
    DeviceProfile none;  // empty workspace
    EXPECT_EQ(home_position_m(none), Vec3(0.0));
}

}  // namespace
}  // namespace tridex::devices
