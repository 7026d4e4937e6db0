// compute/tools/sample_sweep.hpp - the swept Boolean between two consecutive tool samples (what the sculpt thread
// and journal recovery apply).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "compute/tools/mesh_tool.hpp"
#include "compute/tools/sweep.hpp"
#include "compute/tools/symmetry.hpp"
#include "core/tool_sample.hpp"

namespace tridex::compute {

/// The sweep from sample `from` to sample `to`: to's tool (with `mesh` for a kMesh tool), op and axis (to's
/// orientation applied to the tool axis, over the whole segment; a mesh tool also takes to's full orientation, roll
/// included), the straight path from.position to
/// to.position, and to's material (0 for kSubtract: a cut exposes the workpiece's own material). Returns false
/// (out untouched) when `to` does nothing: op kNone or a tool radius that is not > 0.
bool sample_sweep(const ToolSample& from, const ToolSample& to, std::shared_ptr<const MeshTool> mesh, Sweep& out);

/// Every sweep the step from `from` to `to` applies, appended to `out` in this order: sample_sweep's, then its
/// symmetric copies under to.symmetry about `centre_m` (symmetric_sweeps; centre_m = symmetry_centre of the model's
/// lattice). `mirrored_mesh` is the mirror image of `mesh` (mirrored_mesh_tool), needed only for a kMesh tool under
/// mirror symmetry. Returns the number of sweeps appended: 0 when `to` does nothing, else to.symmetry.copies().
/// Throws tridex::Error as symmetric_sweeps.
std::size_t sample_sweeps(const ToolSample& from, const ToolSample& to, std::shared_ptr<const MeshTool> mesh,
                          const std::shared_ptr<const MeshTool>& mirrored_mesh, const Vec3& centre_m,
                          std::vector<Sweep>& out);

/// Whether a stroke open at sample `from` closes at the next sample `to` (the sweep ending at `to` then belongs to
/// the next stroke): `to` does not cut (op kNone or a tool radius that is not > 0), or cuts with another op,
/// material, tool kind, size or mesh, or symmetry than `from`.
bool sample_closes_stroke(const ToolSample& from, const ToolSample& to);

}  // namespace tridex::compute
