// compute/tools/sample_sweep.hpp - the swept Boolean between two consecutive tool samples (what the sculpt thread
// and journal recovery apply).
#pragma once

#include <memory>

#include "compute/tools/mesh_tool.hpp"
#include "compute/tools/sweep.hpp"
#include "core/tool_sample.hpp"

namespace tridex::compute {

/// The sweep from sample `from` to sample `to`: to's tool (with `mesh` for a kMesh tool), op and axis (to's
/// orientation applied to the tool axis, over the whole segment; a mesh tool also takes to's full orientation, roll
/// included), the straight path from.position to
/// to.position, and to's material (0 for kSubtract: a cut exposes the workpiece's own material). Returns false
/// (out untouched) when `to` does nothing: op kNone or a tool radius that is not > 0.
bool sample_sweep(const ToolSample& from, const ToolSample& to, std::shared_ptr<const MeshTool> mesh, Sweep& out);

}  // namespace tridex::compute
