// compute/tools/sample_sweep.cpp - the sweep between two tool samples.
#include "compute/tools/sample_sweep.hpp"

#include <utility>

namespace tridex::compute {

bool sample_sweep(const ToolSample& from, const ToolSample& to, std::shared_ptr<const MeshTool> mesh, Sweep& out) {
    if (to.op == ToolOp::kNone || !(to.tool.radius_m > 0.0)) return false;
    Sweep sw;
    sw.op = to.op;
    sw.tool = sweep_tool(to.tool, std::move(mesh));
    sw.axis = to.orientation * tool_axis_local();
    if (to.tool.kind == ToolKind::kMesh) sw.orientation = to.orientation;  // a mesh tool turns with its roll too
    sw.path_m = Segment{from.position, to.position};
    sw.material = to.op == ToolOp::kSubtract ? 0 : to.material;
    out = std::move(sw);
    return true;
}

std::size_t sample_sweeps(const ToolSample& from, const ToolSample& to, std::shared_ptr<const MeshTool> mesh,
                          const std::shared_ptr<const MeshTool>& mirrored_mesh, const Vec3& centre_m,
                          std::vector<Sweep>& out) {
    Sweep sw;
    if (!sample_sweep(from, to, std::move(mesh), sw)) return 0;
    if (!to.symmetry.on()) {
        out.push_back(std::move(sw));
        return 1;
    }
    const std::size_t before = out.size();
    symmetric_sweeps(sw, to.symmetry, centre_m, mirrored_mesh, out);
    return out.size() - before;
}

bool sample_closes_stroke(const ToolSample& from, const ToolSample& to) {
    const bool cuts = to.op != ToolOp::kNone && to.tool.radius_m > 0.0;
    return !cuts || to.op != from.op || to.material != from.material || to.tool.kind != from.tool.kind ||
           to.tool.radius_m != from.tool.radius_m || to.tool.length_m != from.tool.length_m ||
           to.tool.mesh_id != from.tool.mesh_id || to.symmetry != from.symmetry;
}

}  // namespace tridex::compute
