// Tests of haptics/workspace_mapping: Peng et al.'s workspace moving (press-release jump, hold-drag,
// modelling paused, box centred on the tool), clutching, scaling and the bubble, driven sample by
// sample (exact answers, tolerance 1e-12 m for sums of a few metre-scale terms).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "devices/haptic_device.hpp"
#include "haptics/workspace_mapping.hpp"

namespace tridex::haptics {
namespace {

using devices::DeviceProfile;
using devices::DeviceState;

constexpr double kTol = 1e-12;  // m
constexpr std::uint32_t kButton = 1u;

// Device -> world: 90 degrees about world z (device x -> world y), origin at (1, 2, 3) m, scale 2.
Pose mapping() {
    Pose p;
    p.orientation = glm::angleAxis(glm::radians(90.0), Vec3(0.0, 0.0, 1.0));
    p.position = Vec3(1.0, 2.0, 3.0);
    return p;
}
constexpr double kScale = 2.0;

DeviceState sample(const Vec3& p, std::uint32_t buttons, double t) {
    DeviceState s;
    s.t_s = t;
    s.pose.position = p;
    s.buttons = buttons;
    return s;
}

WorkspaceMapper make(WorkspaceConfig cfg) {
    return WorkspaceMapper(cfg, mapping(), kScale, DeviceProfile::phantom_omni().workspace_m);
}

// The mapping's own formula, to compare against: R * (s * p) + offset.
Vec3 world(const Vec3& p, const Vec3& offset) { return mapping().orientation * (kScale * p) + offset; }

void expect_near(const Vec3& a, const Vec3& b, double tol, const std::string& what) {
    EXPECT_NEAR(glm::length(a - b), 0.0, tol) << what << ": (" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x
                                              << ", " << b.y << ", " << b.z << ")";
}

TEST(WorkspacePeng, IdleIsThePlainMapAndTheBoxIsTheDeviceWorkspace) {
    WorkspaceMapper m = make({});
    const Vec3 p(0.03, 0.01, -0.005);
    const WorkspaceFrame& f = m.update(sample(p, 0, 0.001), 1e-3);
    EXPECT_EQ(f.tool_world.position, world(p, mapping().position));  // bit-exact: same arithmetic
    EXPECT_FALSE(f.modelling_paused);
    EXPECT_TRUE(f.coupled);
    EXPECT_FALSE(f.mapping_changed);
    expect_near(f.box.position, mapping().position, kTol, "box centre");  // Omni workspace centred on 0
    const Vec3 half = 0.5 * DeviceProfile::phantom_omni().workspace_m.size();
    expect_near(f.box_half_extents_m, kScale * half, kTol, "half extents");
    EXPECT_EQ(f.box.orientation, mapping().orientation);
    EXPECT_EQ(f.bubble_radius_m, 0.0);
    EXPECT_EQ(f.force_n, Vec3(0.0));
}

// Press and release with the stylus held off-centre at p: the press centres the box on the tool, the
// release moves the workspace there, and the tool jumps by jump_gain * R * s * (p - c), c = 0.
TEST(WorkspacePeng, PressReleaseJumpsInTheToolsDirection) {
    for (double gain : {1.0, 0.5}) {
        WorkspaceConfig cfg;
        cfg.jump_gain = gain;
        WorkspaceMapper m = make(cfg);
        const Vec3 p(0.03, 0.01, -0.005);
        const Vec3 step = gain * (mapping().orientation * (kScale * p));  // world jump per press-release
        double t = 0.0;
        Vec3 tool = m.update(sample(p, 0, t += 1e-3), 1e-3).tool_world.position;
        for (int k = 1; k <= 4; ++k) {
            const Vec3 centre_before = m.workspace_centre_m();
            const WorkspaceFrame press = m.update(sample(p, kButton, t += 1e-3), 1e-3);
            EXPECT_TRUE(press.modelling_paused);
            EXPECT_TRUE(press.coupled);
            EXPECT_EQ(press.tool_world.position, tool);  // the press itself moves nothing
            // Box centred on the tool (gain 1) or part way there.
            expect_near(press.box.position, centre_before + gain * (tool - centre_before), kTol, "box at press");
            const WorkspaceFrame rel = m.update(sample(p, 0, t += 1e-3), 1e-3);
            EXPECT_TRUE(rel.modelling_paused) << "release tick is paused: no sweep across the jump";
            EXPECT_TRUE(rel.mapping_changed);
            expect_near(rel.box.position, press.box.position, kTol, "workspace coincides with the box");
            expect_near(rel.tool_world.position, tool + step, kTol, "jump");
            tool = rel.tool_world.position;
            const WorkspaceFrame idle = m.update(sample(p, 0, t += 1e-3), 1e-3);
            EXPECT_FALSE(idle.modelling_paused);
            EXPECT_FALSE(idle.mapping_changed);
            EXPECT_EQ(idle.tool_world.position, tool);
            expect_near(m.workspace_centre_m(), mapping().position + static_cast<double>(k) * step, kTol,
                        "centre after k jumps");
        }
    }
}

// Holding the button drags the box with the tool (drag_gain 1: the box stays centred on it); the tool
// keeps the old mapping while held; the release moves the workspace to the box.
TEST(WorkspacePeng, HoldDragsTheBoxAndReleaseMovesTheWorkspace) {
    for (double drag : {1.0, 0.25}) {
        WorkspaceConfig cfg;
        cfg.drag_gain = drag;
        WorkspaceMapper m = make(cfg);
        const Vec3 o = mapping().position;
        const Vec3 p0(0.0, 0.0, 0.0);
        double t = 0.0;
        m.update(sample(p0, 0, t += 1e-3), 1e-3);
        const WorkspaceFrame press = m.update(sample(p0, kButton, t += 1e-3), 1e-3);
        expect_near(press.box.position, world(p0, o), kTol, "box centred on the tool at the press");
        Vec3 p = p0;
        for (int i = 1; i <= 40; ++i) {  // drag 40 mm along device +x
            p = Vec3(1e-3 * i, 0.0, 0.0);
            const WorkspaceFrame& f = m.update(sample(p, kButton, t += 1e-3), 1e-3);
            EXPECT_TRUE(f.modelling_paused);
            expect_near(f.tool_world.position, world(p, o), kTol, "tool follows the old mapping while held");
            expect_near(f.box.position, world(p0, o) + drag * (world(p, o) - world(p0, o)), kTol, "dragged box");
        }
        const Vec3 box = m.frame().box.position;
        const WorkspaceFrame rel = m.update(sample(p, 0, t += 1e-3), 1e-3);
        EXPECT_TRUE(rel.modelling_paused);
        EXPECT_TRUE(rel.mapping_changed);
        expect_near(m.workspace_centre_m(), box, kTol, "workspace = box");
        expect_near(rel.tool_world.position, box + mapping().orientation * (kScale * p), kTol, "tool in the new workspace");
        EXPECT_FALSE(m.update(sample(p, 0, t += 1e-3), 1e-3).modelling_paused);
    }
}

TEST(WorkspacePeng, ButtonHeldAtTheFirstSampleCountsAsAPress) {
    WorkspaceMapper m = make({});
    const Vec3 p(0.02, 0.0, 0.0);
    const WorkspaceFrame f = m.update(sample(p, kButton, 0.001), 1e-3);
    EXPECT_TRUE(f.modelling_paused);
    expect_near(f.box.position, world(p, mapping().position), kTol, "box on the tool");
    // Another button bit is not the workspace button.
    WorkspaceMapper m2 = make({});
    EXPECT_FALSE(m2.update(sample(p, 2u, 0.001), 1e-3).modelling_paused);
}

// Clutching: the press freezes the tool (uncoupled, paused), the box shows the workspace the stylus
// would get, the release continues from the frozen point without a jump.
TEST(WorkspaceClutching, DeclutchFreezesAndReclutchContinues) {
    WorkspaceConfig cfg;
    cfg.mode = WorkspaceMode::kClutching;
    WorkspaceMapper m = make(cfg);
    const Vec3 o = mapping().position;
    const Quat r = mapping().orientation;
    const Vec3 p0(0.03, 0.0, 0.0), p1(-0.03, 0.01, 0.0), p2(-0.01, 0.01, 0.005);
    double t = 0.0;
    const Vec3 frozen = m.update(sample(p0, 0, t += 1e-3), 1e-3).tool_world.position;
    const WorkspaceFrame press = m.update(sample(p0, kButton, t += 1e-3), 1e-3);
    EXPECT_FALSE(press.coupled);
    EXPECT_TRUE(press.modelling_paused);
    EXPECT_EQ(press.tool_world.position, frozen);
    for (int i = 0; i <= 10; ++i) {  // the stylus travels back while declutched
        const Vec3 p = p0 + (static_cast<double>(i) / 10.0) * (p1 - p0);
        const WorkspaceFrame& f = m.update(sample(p, kButton, t += 1e-3), 1e-3);
        EXPECT_EQ(f.tool_world.position, frozen);
        EXPECT_FALSE(f.coupled);
        expect_near(f.box.position, frozen - r * (kScale * p), kTol, "box = the re-clutch workspace");
    }
    const WorkspaceFrame rel = m.update(sample(p1, 0, t += 1e-3), 1e-3);
    EXPECT_TRUE(rel.coupled);
    EXPECT_TRUE(rel.mapping_changed);
    expect_near(rel.tool_world.position, frozen, kTol, "no jump at re-clutch");
    const WorkspaceFrame next = m.update(sample(p2, 0, t += 1e-3), 1e-3);
    EXPECT_FALSE(next.modelling_paused);
    expect_near(next.tool_world.position, frozen + r * (kScale * (p2 - p1)), kTol, "continues from the frozen point");
    expect_near(m.offset_m(), o + r * (kScale * (p0 - p1)), kTol, "offset moved by the declutched travel");
}

TEST(WorkspaceScaling, FixedGainIgnoresTheButton) {
    WorkspaceConfig cfg;
    cfg.mode = WorkspaceMode::kScaling;
    const double gain = 3.0;
    WorkspaceMapper m(cfg, mapping(), gain, DeviceProfile::phantom_omni().workspace_m);
    double t = 0.0;
    for (std::uint32_t b : {0u, 1u, 0u, 1u}) {
        const Vec3 p(0.01 * b + 0.004, -0.02, 0.003);
        const WorkspaceFrame& f = m.update(sample(p, b, t += 1e-3), 1e-3);
        EXPECT_EQ(f.tool_world.position, mapping().orientation * (gain * p) + mapping().position);
        EXPECT_FALSE(f.modelling_paused);
        EXPECT_FALSE(f.mapping_changed);
        expect_near(f.box_half_extents_m, gain * 0.5 * DeviceProfile::phantom_omni().workspace_m.size(), kTol, "box");
    }
    // A 10 mm device move is 30 mm in the world.
    const Vec3 a = m.update(sample(Vec3(0.0), 0, t += 1e-3), 1e-3).tool_world.position;
    const Vec3 b = m.update(sample(Vec3(0.0, 0.0, 0.01), 0, t += 1e-3), 1e-3).tool_world.position;
    EXPECT_NEAR(glm::length(b - a), 0.03, kTol);
}

// Bubble: inside the sphere pure position control; outside, the workspace drifts at
// v = rate * (e / R_b)^3 along the stylus direction, and the wall pushes back with -k * e.
TEST(WorkspaceBubble, PositionControlInsideRateControlOutside) {
    WorkspaceConfig cfg;
    cfg.mode = WorkspaceMode::kBubble;
    WorkspaceMapper m = make(cfg);
    const double rb = m.config().bubble_radius_m;
    EXPECT_NEAR(rb, 0.8 * 0.5 * 0.0254 * 2.8, 1e-15);  // 0.8 * the Omni's half depth = 28.448 mm
    const Vec3 o = mapping().position;
    const Quat r = mapping().orientation;
    double t = 0.0;
    for (int i = 0; i <= 20; ++i) {  // inside: a circle of radius 0.9 R_b
        const double a = 0.3 * i;
        const Vec3 p = 0.9 * rb * Vec3(std::cos(a), std::sin(a), 0.0);
        const WorkspaceFrame& f = m.update(sample(p, 0, t += 1e-3), 1e-3);
        EXPECT_EQ(f.tool_world.position, world(p, o));
        EXPECT_EQ(f.force_n, Vec3(0.0));
        EXPECT_FALSE(f.modelling_paused);
        EXPECT_NEAR(f.bubble_radius_m, kScale * rb, 1e-15);
        expect_near(f.bubble_centre_m, o, kTol, "bubble centre");
    }
    EXPECT_EQ(m.offset_m(), o);
    // Outside by e = R_b / 2 along device (0.6, 0, 0.8): speed = 0.5 m/s * (1/2)^3 = 62.5 mm/s.
    const Vec3 u(0.6, 0.0, 0.8);
    const double e = 0.5 * rb;
    const Vec3 p = (rb + e) * u;
    const int n = 200;
    const double dt = 1e-3;
    for (int i = 0; i < n; ++i) {
        const WorkspaceFrame& f = m.update(sample(p, 0, t += dt), dt);
        expect_near(f.force_n, -cfg.bubble_stiffness_n_per_m * e * (r * u), 1e-12, "bubble wall force");
    }
    const double speed = 0.5 * std::pow(0.5, 3.0);
    expect_near(m.offset_m(), o + (speed * n * dt) * (r * u), 1e-12, "drift = speed * time");
    expect_near(m.frame().tool_world.position, world(p, m.offset_m()), kTol, "tool rides the drifting workspace");
    // Back inside: the drift stops where it is.
    const Vec3 held = m.offset_m();
    m.update(sample(Vec3(0.0), 0, t += dt), dt);
    EXPECT_EQ(m.offset_m(), held);
}

TEST(WorkspaceMapper, ResetRestoresTheInitialMapping) {
    WorkspaceMapper m = make({});
    const Vec3 p(0.03, 0.0, 0.0);
    m.update(sample(p, kButton, 0.001), 1e-3);
    m.update(sample(p, 0, 0.002), 1e-3);
    EXPECT_NE(m.offset_m(), mapping().position);
    m.reset();
    EXPECT_EQ(m.offset_m(), mapping().position);
    EXPECT_FALSE(m.update(sample(p, 0, 0.003), 1e-3).modelling_paused);
}

TEST(WorkspaceMapper, RejectsBadParametersAndNamesTheField) {
    const Aabb ws = DeviceProfile::phantom_omni().workspace_m;
    auto expect_error = [&](WorkspaceConfig cfg, const std::string& field) {
        try {
            WorkspaceMapper m(cfg, mapping(), kScale, ws);
            ADD_FAILURE() << "no throw for " << field;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("WorkspaceConfig." + field), std::string::npos) << e.what();
        }
    };
    WorkspaceConfig c;
    c.jump_gain = -1.0;
    expect_error(c, "jump_gain");
    c = {};
    c.drag_gain = std::nan("");
    expect_error(c, "drag_gain");
    c = {};
    c.mode = WorkspaceMode::kClutching;
    c.button_mask = 0;
    expect_error(c, "button_mask");
    c = {};
    c.bubble_rate_exponent = 0.5;
    expect_error(c, "bubble_rate_exponent");
    c = {};
    c.bubble_radius_m = -0.01;
    expect_error(c, "bubble_radius_m");
    c = {};
    c.mode = WorkspaceMode::kBubble;  // no workspace to derive a default radius from
    try {
        WorkspaceMapper m(c, mapping(), kScale, Aabb{});
        ADD_FAILURE() << "no throw for an empty workspace in bubble mode";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("bubble_radius_m"), std::string::npos) << e.what();
    }
    // Mode names round-trip; unknown names are refused.
    for (WorkspaceMode mode :
         {WorkspaceMode::kPengMoving, WorkspaceMode::kScaling, WorkspaceMode::kClutching, WorkspaceMode::kBubble})
        EXPECT_EQ(parse_workspace_mode(to_string(mode)), mode);
    EXPECT_THROW(parse_workspace_mode("teleport"), Error);
}

}  // namespace
}  // namespace tridex::haptics
