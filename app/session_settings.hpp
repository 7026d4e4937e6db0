// app/session_settings.hpp - everything that decides a session's result, so a recording can carry
// it and a replay can rebuild the same session (issue 4: replay gives the same model).
#pragma once

#include <string>

#include "core/math.hpp"
#include "devices/haptic_device.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app {

/// Workpiece, tool, device and haptics settings of one session (SI units).
struct SessionSettings {
    std::string mesh_path;                   ///< workpiece file (absolute when recorded)
    int resolution = 256;                    ///< lattice cells along the longest side
    double stock_m = 0.3;                    ///< longest side of the placed workpiece, m
    Vec3 workpiece_centre_m{0.0, 0.0, 0.3};  ///< where the workpiece is centred, world m
    double tool_radius_m = 0.008;            ///< ball tool radius (also each contact point's radius), m
    int points = 1;                          ///< contact points: 1 = ball HIP, 2 = wand top/bottom, > 2 = interaction mesh over the ball
    double wand_half_length_m = 0.03;        ///< half length of the wand (points = 2), m
    std::string device = "omni";             ///< device profile: omni | wand | 6dof
    std::string workspace_mode = "peng_moving";  ///< peng_moving | scaling | clutching | bubble (Peng et al. 4.1 and peers)
    double workspace_scale = 1.0;            ///< device -> world gain
    Vec3 device_origin_m{0.0};               ///< world position of the device workspace centre, m
    double stiffness_n_per_m = 700.0;        ///< contact stiffness kp, N/m (0.7 N/mm, Omni-class)
    double damping_n_s_per_m = 0.5;          ///< contact damping kd, N*s/m
    double static_friction = 0.2;            ///< Coulomb static coefficient on the proxy
    double dynamic_friction = 0.15;          ///< Coulomb dynamic coefficient (<= static)
    bool cutting = true;                     ///< reaction force against the tool's advance while carving
    double period_s = 1e-3;                  ///< haptic loop period, s
    std::string op = "subtract";             ///< what the tool does: subtract | union | paint
    int material = 1;                        ///< material id union adds and paint sets (1..7, the palette); cuts expose 0
};

/// The ToolOp named by `name` (subtract, union, paint); throws tridex::Error listing the names.
ToolOp parse_tool_op(const std::string& name);

/// The device profile named by `name` (omni, wand, 6dof); throws tridex::Error listing the names.
devices::DeviceProfile device_profile(const std::string& name);

/// The haptic loop configuration for these settings, with `max_ticks` records preallocated (op and material
/// from s.op, s.material). The same settings always give the same configuration. Throws tridex::Error
/// naming the field on an impossible value (points outside 1..64, friction order, unknown workspace mode,
/// unknown op, material outside 1..7).
haptics::HapticLoopConfig loop_config(const SessionSettings& s, std::size_t max_ticks);

/// Settings as one line of JSON (for a recording's header notes).
std::string settings_to_json(const SessionSettings& s);

/// Parses settings_to_json's output; throws tridex::Error "<source>: settings field '<name>': ..." on a
/// missing or ill-typed field.
SessionSettings settings_from_json(const std::string& text, const std::string& source);

}  // namespace tridex::app
