// haptics/elastic_object.hpp - an elastic ball (a squeeze ball): the force of the tool's interaction mesh against its
// undeformed reference surface, and the drawn surface dented within a radius of influence until the tool lets go.
#pragma once

#include <array>
#include <string>

#include "core/math.hpp"
#include "core/pose.hpp"
#include "core/tri_mesh.hpp"
#include "haptics/tool_points.hpp"

namespace tridex::haptics {

/// An elastic sphere (SI units). Its reference (undeformed) surface is the sphere itself; the force and the
/// deformation are both computed against it, so the object always springs back to it (Popescu, Burdea, Bouzit,
/// "VR Simulation Modeling for a Haptic Glove", 3.3: elastic deformation within a radius of influence).
struct ElasticSphere {
    Vec3 centre_m{0.0};                ///< centre, world m
    double radius_m = 0.03;            ///< radius of the undeformed surface, m, > 0
    double stiffness_n_per_m = 300.0;  ///< k of F_m = k*d_m*N_m, N/m, > 0
    double influence_m = 0.015;        ///< radius of influence r, m, in (0, radius_m]
};

/// Checks an ElasticSphere: finite centre, radius > 0, stiffness > 0, influence in (0, radius]. Throws
/// tridex::Error "<what>: field '<name>': ..." naming the bad field (radius_m, stiffness_n_per_m, influence_radius_m,
/// centre_m).
void validate(const ElasticSphere& sphere, const std::string& what);

/// One interaction point of the tool inside the undeformed surface.
struct ElasticContact {
    Vec3 surface_m{0.0};     ///< the point's projection on the undeformed surface (the interaction point), world m
    Vec3 normal{0.0};        ///< outward unit normal of the undeformed surface at surface_m
    double depth_m = 0.0;    ///< d_m: penetration of the point (with its ball) into the undeformed surface, m, > 0
};

/// The interaction points in contact (fixed storage, no allocation: the haptic thread may use it).
struct ElasticContacts {
    int count = 0;
    std::array<ElasticContact, kMaxToolPoints> contact{};
    /// Largest d_m over the contacts, m (0 without contact).
    double max_depth_m() const;
};

/// The tool's points (P_m = R*T_m + P_w, each with the points' ball radius rho) that lie inside the undeformed
/// sphere: d_m = radius + rho - |P_m - centre| > 0, the interaction point centre + radius * n_m with n_m the unit
/// direction from the centre to P_m (+y for a point exactly at the centre). A non-finite pose gives no contact.
/// O(points); allocates nothing.
ElasticContacts elastic_contacts(const ElasticSphere& sphere, const ToolPoints& points, const Pose& tool_world);

/// The penalty force of contacts against a rigid or undeformed surface, N: F = k * max_m d_m * N, N the unit sum of
/// the contacts' outward normals n_m weighted by their depths d_m (Popescu 3.2, distance-weighted normals), k =
/// stiffness_n_per_m (N/m), clamped to max_force_n (N, > 0; a non-positive or non-finite limit, or no contact, gives
/// zero force). Allocates nothing.
Vec3 penetration_force(double stiffness_n_per_m, const ElasticContacts& contacts, double max_force_n);

/// The force on the tool, N, from the undeformed reference whatever the drawn surface shows (Popescu 3.3):
/// F = k * max_m d_m * N, N the unit sum of the contacts' outward normals n_m weighted by their depths d_m (Popescu
/// 3.2, distance-weighted normals), clamped to max_force_n (N, > 0; a non-positive or non-finite limit gives zero
/// force). For one ball point this is k times the ball's penetration into the undeformed sphere along its normal. The
/// magnitude follows the deepest point, not the sum of k*d_m over the points (Popescu 3.1), so that k means the same
/// N/m whatever the number of interaction points: the sum would make a 64-point tool feel the ball several times
/// stiffer than a single HIP. Allocates nothing.
Vec3 elastic_force(const ElasticSphere& sphere, const ElasticContacts& contacts, double max_force_n);

/// The drawn surface under the contacts: every vertex v of `reference` (the undeformed surface, world m) moves by
/// u(v) = -d_m * k(|v - s_m|) * n_m for the contact m with the largest d_m * k, where k(x) = 1 - (x/r)^2 within the
/// radius of influence r = influence_m and 0 beyond (Popescu 3.3: the largest displacement wins where several
/// interaction points act). With no contacts `deformed` equals `reference` exactly (the object springs back).
/// `deformed` is resized to the reference (its triangles copied only when their count differs). O(vertices x
/// contacts).
void deform_elastic_mesh(const TriMesh& reference, const ElasticContacts& contacts, double influence_m,
                         TriMesh& deformed);

/// Largest distance (m) between corresponding vertices of two meshes with the same vertex count; throws
/// tridex::Error when the counts differ.
double max_vertex_displacement_m(const TriMesh& a, const TriMesh& b);

}  // namespace tridex::haptics
