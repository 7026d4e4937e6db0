// compute/tools/symmetry.hpp - the symmetric poses of a tool pose or a sweep: mirror planes through the workpiece's
// centre, or radial copies about an axis through it (core/symmetry.hpp names them).
#pragma once

#include <memory>
#include <vector>

#include "compute/model/lattice.hpp"
#include "compute/tools/mesh_tool.hpp"
#include "compute/tools/sweep.hpp"
#include "core/pose.hpp"
#include "core/symmetry.hpp"

namespace tridex::compute {

/// One symmetric copy: the map x -> centre + linear * (x - centre) (world m). `linear` is orthogonal: a proper
/// rotation (radial copies, and an even number of mirror planes) or, when `mirrored`, an improper one (det -1).
struct SymmetryTransform {
    glm::dmat3 linear{1.0};
    bool mirrored = false;  ///< det(linear) = -1: the copy is the mirror image of the tool
};

/// The symmetric copies of `s`, the identity first: for mirrors every subset of the planes (bit order: none, x, y,
/// xy, z, xz, yz, xyz, those present), each a diagonal matrix of +-1 (exact); for radial copies the rotations by
/// 2 pi k / N (k = 0..N-1) about the axis (cos and sin in double; k = 0 is exactly the identity). Size s.copies().
/// Throws tridex::Error when !valid_symmetry(s).
std::vector<SymmetryTransform> symmetry_transforms(const Symmetry& s);

/// The centre every symmetry is taken about: the middle of the lattice's node box (world m). Lattice nodes map to
/// lattice nodes under every mirror, so a mirrored ray is again a ray of the model.
Vec3 symmetry_centre(const Lattice& lattice);

/// The tool-frame reflection a mirrored copy applies before its world rotation: x -> -x. It keeps the tool axis
/// (+y, and +z of the axis-only mesh frame), so a ball or a flat-end mill, symmetric under it, is its own mirror
/// image, and a mesh tool's mirror image is the mesh reflected so (mirrored_mesh_tool).
glm::dmat3 tool_frame_reflection();

/// The pose of copy `t` of a tool at `pose` (world m): position centre + linear * (position - centre); orientation
/// linear * R for a rotation, linear * R * tool_frame_reflection() for a mirror (a proper rotation again), which
/// places the mirror image of the tool when the tool's shape is taken reflected (mirrored_mesh_tool).
Pose symmetric_pose(const SymmetryTransform& t, const Vec3& centre_m, const Pose& pose);

/// The mirror image of a mesh tool across its frame's x = 0 plane (tool_frame_reflection; same rays per cell).
/// MeshTool::create turns the inside-out reflected mesh right again. Throws tridex::Error as MeshTool::create.
std::shared_ptr<const MeshTool> mirrored_mesh_tool(const MeshTool& tool);

/// Appends to `out` the copies of `sweep` under `s` about `centre_m`, the identity copy first and bit for bit
/// `sweep`: each copy's path ends and axis mapped by the transform, a kMesh copy's full orientation set to the
/// symmetric pose's (symmetric_pose) and, for a mirrored copy, its tool taken as `mirrored_mesh` (the
/// mirrored_mesh_tool of sweep.tool.mesh). Op, material and sizes are kept. Throws tridex::Error when !valid_symmetry(s),
/// or when a mirrored copy of a kMesh sweep is needed and `mirrored_mesh` is null.
void symmetric_sweeps(const Sweep& sweep, const Symmetry& s, const Vec3& centre_m,
                      const std::shared_ptr<const MeshTool>& mirrored_mesh, std::vector<Sweep>& out);

}  // namespace tridex::compute
