// app/scene/reference_prepare.cpp - a session's reference objects made ready: meshes placed, distance fields built,
// how they are drawn.
#include "app/scene/reference_objects.hpp"

#include <algorithm>
#include <chrono>
#include <memory>

#include "compute/contour/distance_grid_build.hpp"
#include "compute/mesh/mesh_io.hpp"
#include "core/error.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

TriMesh load_reference_mesh(const ReferenceSpec& r) {
    TriMesh m = compute::load_closed_mesh(r.mesh_path);
    const Aabb box = m.bounds();
    const Vec3 ext = box.hi - box.lo;
    const double longest = std::max({ext.x, ext.y, ext.z});
    if (!(longest > 0.0)) throw Error(r.mesh_path + ": the mesh has no extent");
    const Vec3 centre = 0.5 * (box.lo + box.hi);
    const double scale = r.size_m / longest;
    for (Vec3& v : m.positions) v = (v - centre) * scale;
    return m;
}

std::vector<PreparedReference> prepare_references(const std::vector<ReferenceSpec>& refs) {
    std::vector<PreparedReference> out;
    for (const ReferenceSpec& r : refs) {
        const auto t0 = std::chrono::steady_clock::now();
        PreparedReference p;
        try {
            p.mesh_m = load_reference_mesh(r);
            const double cell = r.grid_cell_m > 0.0 ? r.grid_cell_m : std::max(r.size_m / kReferenceGridCells, kReferenceMinCellM);
            p.object.grid = std::make_shared<const DistanceGrid>(
                compute::build_distance_grid(p.mesh_m, cell, kReferenceMarginM, std::size_t{256} << 20));
        } catch (const Error& e) {
            throw Error("reference '" + r.name + "': " + e.what());
        }
        p.object.pose = Pose{r.position_m, r.orientation};
        p.object.stiffness_n_per_m = r.stiffness_n_per_m;
        p.build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        out.push_back(std::move(p));
    }
    return out;
}

renderer::SceneObject reference_scene_object(const ReferenceSpec& r, const TriMesh& mesh_m) {
    renderer::SceneObject o{&mesh_m, glm::vec4(glm::vec3(r.colour), static_cast<float>(r.alpha))};
    o.world_from_model = world_from_reference(r);
    return o;
}

}  // namespace tridex::app
