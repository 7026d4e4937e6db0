// haptics/multipoint.hpp - multi-point contact: one god-object per tool point, total force and torque.
#pragma once

#include <array>
#include <vector>

#include "core/active_surface.hpp"
#include "core/math.hpp"
#include "core/pose.hpp"
#include "haptics/god_object.hpp"
#include "haptics/tool_points.hpp"
#include "haptics/wrench_output.hpp"

namespace tridex::haptics {

/// The contact state of one tool point after an update (world frame).
struct PointState {
    Vec3 world_m{0.0};    ///< P_i = R*T_i + P_w, m
    Vec3 proxy_m{0.0};    ///< the point's god-object, m (= world_m when free)
    Vec3 force_n{0.0};    ///< the point's own force, N: F_i (proxies) or F_m (mesh, before the 1/cos q gain)
    Vec3 normal{0.0};     ///< outward unit normal of the object at the point's contact, zero when free
    double depth_m = 0.0; ///< penetration depth along that normal, m (0 when free)
    bool contact = false; ///< the point's god-object is in contact
    bool hip_inside = false;  ///< a reading of the snapshot puts the point inside material (ContactResult)
};

/// One multi-point update: the wrench about the tool centre and the per-point states.
struct MultiPointResult {
    Wrench wrench;                                  ///< total force (N) and torque about the tool centre (N*m), world
    int points = 0;                                 ///< points evaluated (= the tool's count; 0 after a bad pose)
    int in_contact = 0;                             ///< points in contact
    std::array<PointState, kMaxToolPoints> point{}; ///< states of points [0, points)
    double cos_q = 1;                               ///< interaction mesh: cos q of the displayed force; 1 otherwise
};

/// How point contacts combine into one wrench.
enum class MultiPointMode {
    /// Singapogu ch. 3: every point has its own god-object, F_i = K*x_i + D*xdot_i along the object's normal;
    /// F = sum F_i, tau = sum r_i x F_i.
    kIndependentProxies,
    /// Popescu, Burdea, Bouzit 3.1-3.2: every point's god-object gives its depth d_m; F_m = k*d_m*N_m (unit
    /// step, N_m = the tool's inward normal at m, no damping), F_displayed = (sum F_m)/cos(q); the torque
    /// sum r_m x F_m gets the same 1/cos(q) gain. See display_mesh_force.
    kInteractionMesh,
};

/// Multi-point haptic rendering of a rigid tool against the active surface. Each tool point T_i is mapped to
/// the world by the tool pose (P_i = R*T_i + P_w) and drives its own GodObject (with the shared contact
/// parameters, the ball radius taken from ToolPoints::radius_m). The torque is about the TOOL CENTRE P_w
/// (r_i = R*T_i, not the world origin), so it does not change when the scene and tool move together.
/// Source: Singapogu, MS thesis (Clemson 2007), ch. 3 (5-DOF multi-point rendering and torque).
/// update() allocates nothing, locks nothing and does no I/O: about (points x one god-object update).
class MultiPointRenderer {
public:
    /// points: the tool's contact points (validated; kInteractionMesh needs unit normals on every point).
    /// params: stiffness, damping, etc. of every point's god-object (tool_radius_m is replaced by
    /// points.radius_m). Throws tridex::Error naming the field when points or params are invalid.
    MultiPointRenderer(const ToolPoints& points, const ContactParams& params,
                       MultiPointMode mode = MultiPointMode::kIndependentProxies);

    /// One update for the tool at tool_world (tool frame -> world; position m, unit quaternion) against
    /// `surface`; dt_s (s) since the previous update (the damping term needs dt_s > 0). A non-finite pose
    /// resets every god-object and gives a zero result with points = 0. The returned reference stays valid
    /// until the next update() or reset().
    const MultiPointResult& update(const ActiveSurface& surface, const Pose& tool_world, double dt_s);
    /// Forgets every point's proxy and contact history and clears the result.
    void reset();
    /// Replaces the points by `points` of the same count (e.g. the same tool at another size) and resets every
    /// god-object. Allocation-free, so the haptic thread may call it. Returns false (nothing changes) when the
    /// count differs or a position or the radius is not finite (radius < 0).
    bool set_points(const ToolPoints& points);
    /// Number of tool points.
    int points() const { return points_.count; }
    /// The combination mode.
    MultiPointMode mode() const { return mode_; }
    /// The tool's points (tool frame).
    const ToolPoints& tool_points() const { return points_; }

private:
    ToolPoints points_;
    MultiPointMode mode_;
    double stiffness_n_per_m_;
    std::vector<GodObject> proxies_;  // one per point, built once
    MultiPointResult result_;
};

}  // namespace tridex::haptics
