// app/scene/tool_mesh.cpp - loading, sizing and placing a session's mesh tool.
#include "app/scene/tool_mesh.hpp"

#include <algorithm>
#include <cmath>

#include "compute/mesh/mesh_io.hpp"
#include "core/error.hpp"

namespace tridex::app {

TriMesh load_tool_mesh(const std::string& path, double size_m) {
    if (!std::isfinite(size_m) || !(size_m > 0.0))
        throw Error(path + ": the tool size must be a positive number of metres, got " + std::to_string(size_m));
    TriMesh m = compute::load_closed_mesh(path);
    const Aabb box = m.bounds();
    const Vec3 size = box.size();
    const double longest = std::max({size.x, size.y, size.z});
    if (!(longest > 0.0) || !std::isfinite(longest)) throw Error(path + ": the tool mesh has no extent");
    const double scale = size_m / longest;
    const Vec3 tip(0.5 * (box.lo.x + box.hi.x), box.lo.y, 0.5 * (box.lo.z + box.hi.z));
    for (Vec3& p : m.positions) p = (p - tip) * scale;
    return m;
}

std::shared_ptr<const compute::MeshTool> make_session_mesh_tool(const std::string& path, double size_m) {
    try {
        return compute::MeshTool::create(load_tool_mesh(path, size_m), compute::MeshTool::kDefaultRaysPerCell, path);
    } catch (const Error& e) {
        const std::string msg = e.what();
        if (msg.rfind(path, 0) == 0) throw;
        throw Error(path + ": " + msg);
    }
}

double tool_mesh_reach_m(const TriMesh& mesh_m, int axis) {
    double r = 0.0;
    for (const Vec3& p : mesh_m.positions) r = std::max(r, -p[axis]);
    return r;
}

}  // namespace tridex::app
