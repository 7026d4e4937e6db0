// haptics/workspace_mapping.hpp - device workspace -> world: Peng's workspace moving, scaling,
// clutching and the bubble technique.
#pragma once

#include <cstdint>
#include <string>

#include "core/aabb.hpp"
#include "core/math.hpp"
#include "core/pose.hpp"
#include "devices/haptic_device.hpp"

namespace tridex::haptics {

/// How the small device workspace reaches a large virtual environment; one per session.
enum class WorkspaceMode : std::uint8_t {
    kPengMoving = 0,  ///< Peng et al., section 4.1: button press/hold/release moves the workspace box
    kScaling = 1,     ///< fixed gain: world = R * (scale * p) + offset, world forces / scale at the device; no buttons
    kClutching = 2,   ///< button = declutch: the tool freezes, re-clutch continues from the frozen point
    kBubble = 3,      ///< Dominjon et al. 2005: position control inside a sphere, rate control outside
};

/// "peng_moving", "scaling", "clutching" or "bubble" (the names report.json uses).
const char* to_string(WorkspaceMode mode);
/// Inverse of to_string; throws tridex::Error ("workspace mode '<name>' is not one of ...") otherwise.
WorkspaceMode parse_workspace_mode(const std::string& name);

/// Parameters of the workspace mapping (SI units; device-frame lengths are stylus metres).
/// The mapping itself (device_to_world rotation R, scale s, initial offset) comes from HapticLoopConfig.
struct WorkspaceConfig {
    WorkspaceMode mode = WorkspaceMode::kPengMoving;  ///< technique of this session
    /// Which DeviceState::buttons bits are "the stylus button": pressed when (buttons & mask) != 0.
    /// Must not be 0 for kPengMoving and kClutching.
    std::uint32_t button_mask = 1u;
    /// kPengMoving: at a press the box centre becomes C + jump_gain * (T_press - C) (C the current
    /// workspace centre in the world, T_press the tool). 1 = the paper's rule, the box centred on the
    /// tool; so one press-release moves the workspace by the tool's offset from the workspace centre.
    /// In [0, 10].
    double jump_gain = 1.0;
    /// kPengMoving: while the button is held the box follows the tool: it moves by
    /// drag_gain * (T - T_press). 1 = the box stays centred on the tool (the paper). In [0, 10].
    double drag_gain = 1.0;
    /// kBubble: radius R_b of the bubble around the device workspace centre, device m (> 0), or 0 for
    /// the default 0.8 * the smallest half extent of the device workspace (Omni: 0.8 * 35.56 mm =
    /// 28.448 mm).
    double bubble_radius_m = 0.0;
    /// kBubble: drift speed of the workspace, world m/s, when the stylus is one bubble radius outside
    /// the bubble; the speed law is v = bubble_rate_m_s * (e / R_b)^bubble_rate_exponent, e = |p - c| - R_b
    /// (> 0 outside), along the stylus direction from the centre. >= 0.
    double bubble_rate_m_s = 0.5;
    /// kBubble: exponent of the speed law; 3 = Dominjon et al.'s cubic (fine control near the
    /// bubble, fast far out). In [1, 5].
    double bubble_rate_exponent = 3.0;
    /// kBubble: the bubble's elastic wall, N/m: outside it the stylus is pushed back toward the centre
    /// with -k * e along the outward direction (Dominjon et al.), so the user feels the rate-control
    /// zone. >= 0 (0 = no wall force).
    double bubble_stiffness_n_per_m = 50.0;
};

/// What the mapper reports each tick (world frame unless stated).
struct WorkspaceFrame {
    Pose tool_world;              ///< tool pose in the world: position (m, the HIP) and orientation
    bool pressed = false;         ///< the stylus button (button_mask) is down this tick
    bool modelling_paused = false;///< no sculpting this tick: ToolSamples carry ToolOp::kNone
    bool coupled = true;          ///< the tool follows the stylus (false while declutched: no contact force)
    bool mapping_changed = false; ///< the workspace moved discontinuously this tick (reset the contact)
    Pose box;                     ///< the workspace box: centre (m) and orientation (box axes = device axes)
    Vec3 box_half_extents_m{0.0}; ///< half extents of the box along its own axes, world m
    Vec3 bubble_centre_m{0.0};    ///< kBubble: bubble centre, m (the workspace centre); else = box centre
    double bubble_radius_m = 0.0; ///< kBubble: bubble radius in the world, m (scale * R_b); 0 in other modes
    Vec3 force_n{0.0};            ///< force the mapping adds (the bubble's wall), N; zero in other modes
};

/// Maps each device sample to the tool pose in the world and keeps the world workspace box.
/// The mapping is T = R * (s * p) + offset (p: stylus position, device frame; R, s: device_to_world
/// rotation and scale; offset starts at device_to_world.position), so with no button activity it is
/// exactly HapticLoop's device -> world map. C = R * (s * c_d) + offset is the workspace centre in the
/// world (c_d: centre of the device workspace); the box has half extents s * (device half extents).
///
/// Button semantics per mode ("press" = the button goes down, "release" = it comes up):
/// - kPengMoving (Peng et al., "Haptic Interface Technique in Large-Scale Virtual Environment",
///   section 4.1): a press pauses modelling and centres the transparent box on the tool
///   (B = C + jump_gain * (T - C)); while held the tool keeps following the stylus with the old
///   mapping and the box is dragged with it (B += drag_gain * (T - T_press)); the release makes the
///   haptic workspace coincide with the box (offset += B - C). The tool then sits at the same device
///   offset in the new workspace, so it jumps by B - C: repeated press-release (stylus held off-centre)
///   moves the workspace in steps of jump_gain * s * R * (p - c_d), i.e. in the direction the tool
///   moved from the workspace centre. Modelling is paused from the press through the release tick
///   (inclusive), so no swept segment spans the jump.
/// - kScaling: the fixed map above; never paused. Forces computed in the world reach the device divided
///   by the gain (force_scale() = 1 / s), so the device shows the world's stiffness as authored: a world
///   spring k and a device displacement dp give a world penetration s * dp, a world force k * s * dp and
///   a device force k * dp (the scaling technique's rule: forces go to the device divided by the gain).
///   Why not s * F (which would conserve energy across the map, F_dev . dp = F_w . (s dp))? It shows
///   k * s^2 at the hand, past the
///   device's stable stiffness (Colgate: K < 2 b / T) for s > 1, while 1 / s keeps the authored stiffness
///   inside it whatever the gain; the map stays passive either way (device power = world power / s^2 >= 0
///   when the world's is), and the safety stage books the energy of the force actually sent over the
///   stylus's physical motion. Torque is not divided: the map does not scale angles, so a world torsion
///   stiffness is shown as it is.
/// - kClutching: a press declutches: the tool freezes at its pose, modelling pauses and the tool is
///   uncoupled (no contact force); the box shows where the workspace will be on re-clutch
///   (offset' = T_frozen - R * (s * p)). The release re-clutches with that offset: the tool continues
///   from the frozen point without a jump (paused on the release tick too).
/// - kBubble (Dominjon et al., "The 'Bubble' Technique", IEEE VR 2005): buttons do nothing. Inside the
///   sphere |p - c_d| <= R_b the map is pure position control; outside, the workspace (offset) drifts
///   at v = bubble_rate_m_s * (e / R_b)^n along R * (p - c_d)/|p - c_d| each tick (offset += v * dt,
///   applied before the tool is mapped) and force_n = -k * e * R * (p - c_d)/|p - c_d|.
/// A press present on the first update counts as a press. update() is allocation-free and O(1).
class WorkspaceMapper {
public:
    /// device_to_world: rotation R (unit quaternion) and the initial offset (m); scale: s > 0;
    /// device_workspace_m: the device's reachable box (DeviceProfile::workspace_m; an empty box is
    /// treated as the single point at the origin). Throws tridex::Error naming the WorkspaceConfig
    /// field when a parameter is out of its documented range, or when the bubble radius resolves to 0.
    WorkspaceMapper(const WorkspaceConfig& cfg, const Pose& device_to_world, double scale, const Aabb& device_workspace_m);

    /// One sample (device frame, finite) and the time step dt_s (s; used by the bubble drift, none
    /// when not > 0). Returns the frame for this tick (valid until the next update or reset).
    const WorkspaceFrame& update(const devices::DeviceState& state, double dt_s);
    /// Back to the initial mapping, button up, nothing frozen.
    void reset();

    /// The frame of the last update (before any update: the initial box, tool at the workspace centre).
    const WorkspaceFrame& frame() const { return frame_; }
    /// The parameters, with bubble_radius_m resolved to its value in device m.
    const WorkspaceConfig& config() const { return cfg_; }
    /// Current translation of the mapping, world m (T = R * (s * p) + offset).
    const Vec3& offset_m() const { return offset_; }
    /// Current world centre of the haptic workspace, m.
    Vec3 workspace_centre_m() const { return map(centre_d_); }
    /// Factor applied to forces computed in the world (contact) before they go to the device: 1 / scale
    /// in kScaling (see above), 1 in the other modes (1:1 position control within the workspace; their
    /// own forces, the bubble wall, are computed in device units already).
    double force_scale() const { return force_scale_; }
    /// Maps a device-frame point (m) with the current mapping, world m.
    Vec3 map(const Vec3& p_device) const { return rot_ * (scale_ * p_device) + offset_; }

private:
    void fill_box(const Vec3& centre_world);

    WorkspaceConfig cfg_;
    Quat rot_;
    double scale_;
    double force_scale_ = 1.0;
    Vec3 initial_offset_;
    Vec3 centre_d_{0.0};      // device workspace centre, device m
    Vec3 half_d_{0.0};        // device workspace half extents, device m
    Vec3 offset_{0.0};
    bool was_pressed_ = false;
    Vec3 press_tool_{0.0};    // Peng: tool position at the press, world m
    Vec3 press_box_{0.0};     // Peng: box centre at the press, world m
    Pose frozen_;             // clutching: the frozen tool pose
    WorkspaceFrame frame_;
};

}  // namespace tridex::haptics
