// app/scene/reference_prepare.cpp - a session's reference objects made ready: meshes placed, distance fields built,
// how they are drawn.
#include "app/scene/reference_objects.hpp"

#include <algorithm>
#include <chrono>
#include <memory>

#include "compute/contour/distance_grid_build.hpp"
#include "compute/mesh/mesh_io.hpp"
#include "compute/model/workpiece.hpp"
#include "core/error.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

TriMesh load_reference_mesh(const ReferenceSpec& r) {
    const TriMesh m = compute::load_closed_mesh(r.mesh_path);
    try {
        return compute::transformed(m, compute::fit_to_stock(m.bounds(), Vec3(0.0), r.size_m));
    } catch (const Error& e) {
        throw Error(r.mesh_path + ": " + e.what());
    }
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
