// core/tool_shape.hpp - the shape of the tool that cuts and touches: one type for the sculpt and haptic threads.
#pragma once

#include <cstdint>
#include <string>

#include "core/math.hpp"

namespace tridex {

/// The kind of tool.
enum class ToolKind : std::uint8_t {
    kBall = 0,     ///< a ball of radius_m centred on the tool origin (ball-end mill, sculpting ball); sweeps a capsule
    kFlatEnd = 1,  ///< a flat-end mill: solid cylinder of radius_m whose flat end is centred on the tool origin and
                   ///< whose shank runs length_m along the tool axis
    kMesh = 2,     ///< any closed mesh (a session's mesh-tool table entry mesh_id), in the tool frame
};

/// Shape and size of a tool, SI units, in the tool frame. Tool-frame convention shared by the haptic
/// contact points (haptics/tool_points.hpp) and the swept Booleans (compute/tools/sweep.hpp): the origin is the
/// tool's reference point (the HIP: a ball's centre, the centre of a flat-end mill's end face, a session mesh
/// tool's tip: its bounding box's centre across the axis at its lowest point along it), the tool
/// axis is +y, pointing from the cutting end toward the hand. Trivially copyable, so a ToolSample carrying
/// it goes through the haptic thread's lock-free ring without allocating.
struct ToolShape {
    ToolKind kind = ToolKind::kBall;
    double radius_m = 0.0;      ///< ball or cylinder radius, m (> 0); kMesh: the mesh's bounding radius about the origin
    double length_m = 0.0;      ///< kFlatEnd: cylinder length along the axis, m (> 0); 0 otherwise
    std::uint32_t mesh_id = 0;  ///< kMesh: index into the session's mesh-tool table; 0 otherwise
};

/// The tool axis in the tool frame: +y (see ToolShape).
inline Vec3 tool_axis_local() { return Vec3(0.0, 1.0, 0.0); }

/// "ball", "flat_end" or "mesh".
const char* to_string(ToolKind kind);

/// Inverse of to_string. Throws tridex::Error "<what>: unknown tool shape 'x'; use ball, flat_end or mesh".
ToolKind parse_tool_kind(const std::string& name, const std::string& what);

/// Largest distance (m) of any point of the tool from its origin: radius_m for a ball (and for kMesh, whose
/// radius_m is its bounding radius), sqrt(radius_m^2 + length_m^2) for a flat-end mill. Non-finite or
/// negative sizes count as 0.
double tool_reach_m(const ToolShape& tool);

/// Checks a tool shape: kind is one of ToolKind, radius_m finite and > 0, kFlatEnd length_m finite and > 0.
/// Throws tridex::Error "<what>.radius_m ..." (or .length_m, .shape) naming the field.
void validate_tool(const ToolShape& tool, const std::string& what);

}  // namespace tridex
