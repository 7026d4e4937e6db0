// app/scene/stroke.hpp - the demo's scripted carving stroke, planned on the scan-converted workpiece.
#pragma once

#include <vector>

#include "compute/model/tridexel.hpp"
#include "core/math.hpp"
#include "core/pose.hpp"
#include "devices/button_script.hpp"

namespace tridex::app {

/// How the hand moves the haptic workspace between two carving passes with Peng et al.'s workspace moving
/// (section 4.1; haptics/workspace_mapping.hpp), with the tool lifted off the surface. Modelling is paused
/// from each press through its release, so nothing is carved while the workspace moves.
enum class WorkspaceMove {
    kJump,  ///< clicks: each press-release with the stylus off-centre jumps the workspace by that offset
    kDrag,  ///< a press, the hand pushing the box ahead while the button is held, a release
};

/// Shape of the demo stroke (SI units).
struct StrokeParams {
    double duration_s = 4.0;      ///< whole script: approach, press, carve, lift
    double length_m = 0.12;       ///< length of the carving pass along world x, centred on the workpiece
    double depth_m = 0.006;       ///< how far the hand aims the ball's lowest point below the surface
    double tool_radius_m = 0.008; ///< distance from the tool origin to its lowest point along the press direction, m (a ball: its radius)
    double clearance_m = 0.03;    ///< height above the surface where the stroke starts and ends
    int press_axis = 2;           ///< world axis the tool presses against: 2 = the side facing the viewer (+z), 1 = the top (+y)
    /// Carving passes along +x, each length_m long in the world and the same hand motion in the device: more than
    /// one carves a groove passes * length_m long, beyond the device's reach, by moving the workspace between
    /// passes (workspace mode peng_moving, jump and drag gains 1).
    int passes = 1;
    /// How the workspace moves after each pass but the last (passes - 1 entries; missing ones are jumps).
    std::vector<WorkspaceMove> moves;
    double workspace_scale = 1.0; ///< device -> world gain s of the session (the hand's motion is length_m / s)
    /// How long the hand waits, lifted above the first pass's start, before the stroke begins, s (>= 0): the
    /// stroke then runs from start_s to start_s + duration_s (a carve that begins once the session has settled).
    double start_s = 0.0;

    /// When the script ends, s: start_s + duration_s.
    double end_s() const { return start_s + duration_s; }
};

/// How long the hand takes to move the workspace between two passes, s.
double workspace_move_s(WorkspaceMove move);

/// Waypoints of the hand's target in world metres, with times; the virtual hand follows them.
struct StrokePlan {
    std::vector<double> t_s;      ///< strictly increasing, from 0 to duration_s
    std::vector<Vec3> world_m;    ///< target tool centre at each time, world m
    Vec3 centre_m{0.0};           ///< middle of the carving pass on the surface (where the device workspace is centred)
    /// Per waypoint, how far the workspace has moved (world m) when the hand is there: zero for a single pass.
    /// The hand's device-frame target is home + (world_m - centre_m - shift_m) / workspace_scale.
    std::vector<Vec3> shift_m;
    /// The button presses and releases of the workspace moves (device time; button 0), empty for one pass.
    std::vector<devices::ButtonStep> buttons;
    /// The hand's targets relative to the device's home, device m (what shift_m and centre_m give).
    std::vector<Vec3> device_offsets_m(double workspace_scale) const;
};

/// The plan placed by a workpiece's pose (plan_stroke plans in its model frame): every waypoint and the centre
/// mapped, the workspace shifts turned, so the hand follows the posed surface. The identity changes nothing.
void place_plan(StrokePlan& plan, const Pose& world_from_model);

/// Plans a pass along world x over the side of the workpiece facing +press_axis (the viewer for
/// axis 2, the sky for axis 1), through the workpiece's middle, placed where that surface is
/// flattest over the pass length (the bunny's flank, not its ears). The surface height under each
/// waypoint comes from the press axis' ray set (compute::probe_top), so the ball follows the surface
/// at depth_m below it. Throws tridex::Error when no ray under the
/// pass holds material (an empty or tiny workpiece).
/// With passes > 1 the groove is passes * length_m long, centred on the workpiece along x: each pass presses in,
/// carves length_m, lifts by clearance_m, and the hand then moves the workspace forward by length_m (params.moves:
/// two clicks with the stylus held at the pass's end, or a press, a drag of half a pass and a release) and goes
/// back, lifted, to where the next pass starts; the hand's motion stays within +-length_m / s of its home along x.
/// Throws tridex::Error when the passes leave less than 0.5 s each, or the groove is longer than the workpiece.
/// With start_s > 0 the hand holds its first waypoint from 0 to start_s and every later time (waypoints and
/// buttons) moves start_s later; a negative or non-finite start_s throws tridex::Error "stroke.start_s: ...".
StrokePlan plan_stroke(const compute::TriDexel& model, const StrokeParams& params);

}  // namespace tridex::app
