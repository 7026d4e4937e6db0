// haptics/tool_points.hpp - contact points on the tool (tool frame) and the rigid map P_i = R*T_i + P_w.
#pragma once

#include <array>
#include <string>

#include "core/math.hpp"
#include "core/pose.hpp"
#include "core/tri_mesh.hpp"
#include "core/tool_shape.hpp"

namespace tridex::haptics {

/// Largest number of contact points a tool can carry (the multi-point renderer's fixed storage).
constexpr int kMaxToolPoints = 64;

/// Contact points on the tool, in the tool frame (m), each with an outward unit normal of the tool surface
/// there (used by the haptic interaction mesh; zero where a point has no surface, e.g. the single centre
/// point). Tool-frame convention of this module: the tool's long axis is +y ("top" at +y, "bottom" at -y).
/// Source: Singapogu MS thesis (Clemson 2007) ch. 3 (points T_i on the wand); Popescu, Burdea, Bouzit,
/// "VR Simulation Modeling for a Haptic Glove" 3.1 (haptic interaction mesh).
struct ToolPoints {
    int count = 0;                                ///< points in use, [1, kMaxToolPoints]
    std::array<Vec3, kMaxToolPoints> local_m{};   ///< T_i: point positions in the tool frame, m
    std::array<Vec3, kMaxToolPoints> normal{};    ///< outward unit normals in the tool frame (or zero)
    double radius_m = 0;                          ///< ball radius around every point, m; 0 = points

    /// One point at the tool centre with a ball of radius radius_m (m): the single-HIP behaviour of the
    /// plain god-object. Its normal is zero (no interaction-mesh surface). Throws tridex::Error when
    /// radius_m is negative or not finite.
    static ToolPoints single(double radius_m);
    /// The thesis's 5-DOF wand: a top point (0, +h, 0) and a bottom point (0, -h, 0) on the tool axis, with
    /// outward normals +y and -y, radius 0. Throws tridex::Error when half_length_m is not finite and > 0.
    static ToolPoints wand(double half_length_m);
    /// A haptic interaction mesh over a ball of radius radius_m (m) centred on the tool centre: `count`
    /// points spread evenly by the Fibonacci (golden-angle) spiral, z_i = 1 - (2i+1)/count,
    /// phi_i = i * pi * (3 - sqrt 5), normals = unit positions, radius 0. Throws tridex::Error when
    /// radius_m is not finite and > 0 or count is not in [1, kMaxToolPoints].
    static ToolPoints sphere_mesh(double radius_m, int count);
    /// A haptic interaction mesh over a flat-end mill's own surface (tool frame of core/tool_shape.hpp: the
    /// flat end's centre at the origin, the shank along +y), `count` points in all, radius 0, every point on
    /// the cylinder's surface: the end face's centre and a ring at half the radius (normal -y; about a fifth
    /// of the points, at least 2 on the ring), the cutting edge (a ring on the end face's rim, normal
    /// bisecting -y and the radial direction; about a third, at least 3) and the rest on side rings at even
    /// heights up to length_m (radial normals), each ring turned half a step against the one before.
    /// Throws tridex::Error when radius_m or length_m is not finite and > 0 or count is not in
    /// [8, kMaxToolPoints]. Source: Popescu, Burdea, Bouzit 3.1 (interaction mesh over the tool's surface).
    static ToolPoints flat_end(double radius_m, double length_m, int count);

    /// These points for the same tool scaled by s about the tool centre (a resized tool: [ and ] at the desk):
    /// positions and the ball radius times s (m), normals and count unchanged. s must be finite and > 0 (not
    /// checked: callers pass a ratio of two checked radii).
    ToolPoints scaled(double s) const {
        ToolPoints p = *this;
        for (int i = 0; i < p.count; ++i) p.local_m[static_cast<std::size_t>(i)] *= s;
        p.radius_m *= s;
        return p;
    }
};

/// Contact points for a session's tool, so that touch and cut agree (the points lie on the tool's own
/// surface; Popescu, Burdea, Bouzit 3.1):
/// - ball: points = 1 -> the single god-object of the ball's radius (the ball's exact contact);
///   3..kMaxToolPoints -> sphere_mesh over the ball;
/// - flat_end: points = 2 -> the thesis's wand (Singapogu 3.4.1): two points, the flat end's centre and the
///   top of the shank, with outward normals -y and +y; otherwise flat_end(radius, length, n) with n = points,
///   or 32 when points is 1 (the default);
/// - mesh: mesh_surface_points(*mesh_m, n) (haptics/mesh_tool_points.hpp) with n = points, or 32 when points
///   is 1 (the default); 8..kMaxToolPoints. `mesh_m` is the tool's mesh in the tool frame, m, as data (this
///   module has no mesh tools: the caller loads it); it must outlive the call only.
/// Throws tridex::Error naming `what` ("tool", "points") for a combination that has no such points (a ball
/// with 2 points, a flat end with 3..7, a mesh tool with 2..7 or without its mesh) or a bad tool (validate_tool).
ToolPoints tool_points_for(const ToolShape& tool, int points, const std::string& what, const TriMesh* mesh_m = nullptr);

/// Checks a ToolPoints: count in [1, kMaxToolPoints], finite positions, radius finite and >= 0, and every
/// normal of the used points either zero or unit length (within 1e-9); when require_normals, every normal
/// must be unit. Throws tridex::Error naming the field (e.g. "ToolPoints.normal[3]") otherwise.
void validate(const ToolPoints& points, bool require_normals);

/// Rotation of `angle_rad` (rad, right-handed) about `axis` (any length, normalised here), as a unit
/// quaternion: the thesis's axis-angle wand pose (Singapogu ch. 3, Table 3 records rotation as axis-angle).
/// Throws tridex::Error when axis is zero or not finite, or angle_rad is not finite.
Quat rotation_from_axis_angle(const Vec3& axis, double angle_rad);

/// World position of the tool-frame point local_m (m): P_i = R*T_i + P_w with R = tool.orientation and
/// P_w = tool.position (Singapogu ch. 3). No checks (the caller passes finite values).
Vec3 tool_point_world(const Pose& tool, const Vec3& local_m);

/// Largest distance (m) of the used points T_i from the tool centre, max_i |T_i| (0 for no points). With
/// ToolPoints::radius_m it sizes the active-surface window: the tool lies within that distance + radius_m
/// of its centre in any pose.
double max_point_distance_m(const ToolPoints& points);

}  // namespace tridex::haptics
