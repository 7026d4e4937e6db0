// app/session/view/symmetry_view.hpp - what symmetry looks like in the scene: the symmetric copies of the tool as
// ghosts, and the mirror planes (or the radial axis) drawn faintly, while symmetry is on.
#pragma once

#include <array>
#include <vector>

#include "core/aabb.hpp"
#include "core/pose.hpp"
#include "core/symmetry.hpp"
#include "core/tool_shape.hpp"
#include "core/tri_mesh.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

/// Translucent colour of a ghost tool (linear RGBA): the tool's blue, fainter, so it reads as "not the one in hand".
inline constexpr glm::vec4 kGhostToolColour{0.45f, 0.65f, 0.95f, 0.35f};
/// Colour of the mirror planes and the radial axis (linear RGBA, faint, unlit).
inline constexpr glm::vec4 kSymmetryPlaneColour{0.60f, 0.80f, 1.00f, 0.10f};

/// Scene objects for the symmetry of a session: ghosts of the tool at each symmetric pose but its own (the copies
/// the sculpt thread applies, compute/tools/symmetry.hpp), and the planes or the axis they are taken about. The
/// ghosts are only drawn: the person feels their own tool's contact alone. Keeps its meshes (uploaded once by the
/// renderer; each frame moves them by SceneObject::world_from_model), so it must outlive the frames that draw them.
class SymmetryGhosts {
public:
    /// `bounds_m`: the workpiece lattice's box (model m; its centre is the symmetry centre, as the sculpt thread's);
    /// `tool_mesh`: a mesh tool's mesh in its tool frame (m), or nullptr (a ball stands in for a mesh tool then).
    /// Throws tridex::Error when the box is empty or not finite.
    SymmetryGhosts(const Aabb& bounds_m, const TriMesh* tool_mesh);

    /// Appends to `out` the planes (mirrors) or the axis (radial copies) of `s`, then a ghost of `tool` (its kind and
    /// size now) at each symmetric copy of `tool_pose` (world) but the identity. Appends nothing when `s` is off or
    /// not valid, or the pose is not finite. `world_from_model`: the workpiece's pose now (the planes and copies are
    /// taken in its model frame, then placed). The objects point into this object's meshes.
    void append(const Symmetry& s, const Pose& tool_pose, const ToolShape& tool, std::vector<renderer::SceneObject>& out,
                const Pose& world_from_model = Pose{}) const;

private:
    Aabb bounds_;
    Vec3 centre_;
    TriMesh sphere_, cylinder_;              // unit shapes, scaled by the transform
    TriMesh mesh_, mirrored_mesh_;           // a mesh tool and its mirror image (x -> -x in its frame)
    std::array<TriMesh, 3> planes_;          // the mirror plane normal to x, y, z through the centre, two-sided
};

}  // namespace tridex::app
