// haptics/reference_object.hpp - a rigid reference object: a closed mesh placed in the scene, felt through its
// signed distance field and never sculpted.
#pragma once

#include <memory>
#include <string>

#include "core/distance_grid.hpp"
#include "core/pose.hpp"
#include "haptics/elastic_object.hpp"
#include "haptics/tool_points.hpp"

namespace tridex::haptics {

/// A rigid object beside the workpiece (SI units): its surface's signed distance field in its own frame, and where
/// that frame stands in the world. The tool's contact points are pushed out of it by a penalty force, as the elastic
/// spheres push them (Popescu, Burdea, Bouzit 3.1-3.2), so it is felt but never changes.
struct ReferenceObject {
    std::shared_ptr<const DistanceGrid> grid;  ///< the surface's signed distance, its own frame, m; shared, never written
    Pose pose;                                 ///< its frame -> world (rigid: unit quaternion, position m)
    double stiffness_n_per_m = 700.0;          ///< k of F = k * d * N, N/m, in (0, 1e5]
};

/// Checks a ReferenceObject: a valid grid (DistanceGrid::valid), a finite position, a unit quaternion (within
/// 1e-6), stiffness in (0, 1e5]. Throws tridex::Error "<what>: field '<name>': ..." naming the bad field (grid, pose,
/// stiffness_n_per_m).
void validate(const ReferenceObject& object, const std::string& what);

/// The tool's points (P_m = R*T_m + P_w, each with the points' ball radius rho) that reach into the object:
/// d_m = rho - D(P_m) > 0 with D the signed distance sampled at P_m in the object's frame. The contact normal is the
/// distance field's gradient turned into the world (outward), and the interaction point P_m - D(P_m) * normal. A point
/// outside the grid's box, a gradient of zero length, or a non-finite pose gives no contact. O(points); allocates
/// nothing.
ElasticContacts reference_contacts(const ReferenceObject& object, const ToolPoints& points, const Pose& tool_world);

}  // namespace tridex::haptics
