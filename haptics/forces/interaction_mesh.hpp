// haptics/forces/interaction_mesh.hpp - the haptic interaction mesh force law: F_m = k*d_m*N_m, F_displayed = sum/cos(q).
#pragma once

#include "core/math.hpp"

namespace tridex::haptics {

/// Smallest cos(q) the displayed-force correction divides by (q <= 78.46 deg): beyond it the gain 1/cos(q)
/// is held at 1/kMinCosQ = 5 so a grazing contact cannot command an unbounded force.
constexpr double kMinCosQ = 0.2;

/// Force of one interaction-mesh point m, N: F_m = k * d_m * u(d_m) * N_m, with u the unit step (only a
/// penetrating point pushes). stiffness_n_per_m = k (N/m), depth_m = d_m (m, the point's penetration along
/// the object's surface normal), inward_normal = N_m (the tool surface's inward unit normal at m, world
/// frame: the direction the object pushes that point). Returns zero for d_m <= 0 or any non-finite input.
/// Source: Popescu, Burdea, Bouzit, "VR Simulation Modeling for a Haptic Glove", 3.1.
Vec3 mesh_point_force(double stiffness_n_per_m, double depth_m, const Vec3& inward_normal);

/// The force an interaction mesh displays, from the sum of its point forces.
struct MeshForce {
    Vec3 displayed_n{0.0};  ///< F_displayed = sum / max(cos q, kMinCosQ), N; zero when cos q <= 0 or no contact
    double cos_q = 1.0;     ///< cos of the angle q between the sum and the contact normal (1 when no contact)
    double gain = 0.0;      ///< displayed_n = gain * sum (0, or 1/max(cos q, kMinCosQ)); the torque uses it too
};

/// Popescu et al. 3.2: the mesh sums point forces along the tool's own surface normals, which for a tilted
/// contact lean by q away from the object's normal, so their normal (penetration-resisting) part is only
/// |sum| * cos(q). F_displayed = sum / cos(q) restores that part to |sum|: for one point at depth d its
/// normal component is k*d (the single-HIP value) whatever the tilt, plus a tangential part k*d*tan(q).
/// sum_n: sum of the F_m (N). contact_normal: the depth-weighted sum of the object's outward normals over
/// the points in contact (any length; its direction is used). Cases: no contact (sum or normal zero) ->
/// zero force, cos_q = 1, gain 0; cos q <= 0 (the mesh normals would pull the tool into the material) ->
/// zero force, gain 0; cos q < kMinCosQ -> gain 1/kMinCosQ; non-finite input -> zero force, cos_q = 1.
MeshForce display_mesh_force(const Vec3& sum_n, const Vec3& contact_normal);

}  // namespace tridex::haptics
