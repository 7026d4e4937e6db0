// app/stroke.hpp - the demo's scripted carving stroke, planned on the scan-converted workpiece.
#pragma once

#include <vector>

#include "compute/model/tridexel.hpp"
#include "core/math.hpp"

namespace tridex::app {

/// Shape of the demo stroke (SI units).
struct StrokeParams {
    double duration_s = 4.0;      ///< whole script: approach, press, carve, lift
    double length_m = 0.12;       ///< length of the carving pass along world x, centred on the workpiece
    double depth_m = 0.006;       ///< how far the hand aims the ball's lowest point below the surface
    double tool_radius_m = 0.008; ///< distance from the tool origin to its lowest point along the press direction, m (a ball: its radius)
    double clearance_m = 0.03;    ///< height above the surface where the stroke starts and ends
    int press_axis = 2;           ///< world axis the tool presses against: 2 = the side facing the viewer (+z), 1 = the top (+y)
};

/// Waypoints of the hand's target in world metres, with times; the virtual hand follows them.
struct StrokePlan {
    std::vector<double> t_s;      ///< strictly increasing, from 0 to duration_s
    std::vector<Vec3> world_m;    ///< target tool centre at each time, world m
    Vec3 centre_m{0.0};           ///< middle of the carving pass on the surface (where the device workspace is centred)
};

/// Plans a pass along world x over the side of the workpiece facing +press_axis (the viewer for
/// axis 2, the sky for axis 1), through the workpiece's middle, placed where that surface is
/// flattest over the pass length (the bunny's flank, not its ears). The surface height under each
/// waypoint comes from the press axis' ray set (compute::probe_top), so the ball follows the surface
/// at depth_m below it. Throws tridex::Error when no ray under the
/// pass holds material (an empty or tiny workpiece).
StrokePlan plan_stroke(const compute::TriDexel& model, const StrokeParams& params);

}  // namespace tridex::app
