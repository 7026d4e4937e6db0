// app/session/view/symmetry_view.cpp - ghost tools and mirror planes.
#include "app/session/view/symmetry_view.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "compute/tools/symmetry.hpp"
#include "core/error.hpp"
#include "renderer/scene/arrow_mesh.hpp"
#include "renderer/scene/plane_marks.hpp"
#include "renderer/scene/primitive_meshes.hpp"

namespace tridex::app {

namespace {

// The plane x_a = centre_a, 5 % beyond the box on each side, as a two-sided rectangle.
TriMesh plane_mesh(const Aabb& box, const Vec3& centre, int a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    const Vec3 size = box.size();
    renderer::PlaneFrame f;
    f.o = centre;
    f.ex = Vec3(0.0);
    f.ey = Vec3(0.0);
    f.n = Vec3(0.0);
    f.ex[u] = 1.0;
    f.ey[v] = 1.0;
    f.n[a] = 1.0;
    TriMesh m;
    const double hu = 0.55 * size[u], hv = 0.55 * size[v];
    renderer::add_plane_rect(m, f, -hu, -hv, hu, hv, 0.0);
    return m;
}

}  // namespace

SymmetryGhosts::SymmetryGhosts(const Aabb& bounds_m, const TriMesh* tool_mesh)
    : bounds_(bounds_m), sphere_(renderer::unit_sphere(12, 24)), cylinder_(renderer::unit_cylinder(24)) {
    if (bounds_m.empty() || !is_finite(bounds_m.lo) || !is_finite(bounds_m.hi))
        throw Error("symmetry view: the workpiece's box is empty or not finite");
    centre_ = 0.5 * (bounds_m.lo + bounds_m.hi);
    if (tool_mesh) {
        mesh_ = *tool_mesh;
        mirrored_mesh_ = *tool_mesh;
        for (Vec3& p : mirrored_mesh_.positions) p.x = -p.x;
        for (auto& t : mirrored_mesh_.triangles) std::swap(t[1], t[2]);  // outward again after the reflection
    }
    for (int a = 0; a < 3; ++a) planes_[a] = plane_mesh(bounds_, centre_, a);
}

void SymmetryGhosts::append(const Symmetry& s, const Pose& tool_pose, const ToolShape& tool,
                            std::vector<renderer::SceneObject>& out, const Pose& world_from_model) const {
    if (!s.on() || !valid_symmetry(s) || !is_finite(tool_pose.position) || !(tool.radius_m > 0.0)) return;
    // Everything below is in the workpiece's model frame, placed into the world by its pose.
    const glm::mat4 placed(world_from_model.matrix());
    const auto add = [&](const TriMesh& m, const glm::mat4& world, const glm::vec4& colour, bool lit) {
        renderer::SceneObject o;
        o.mesh = &m;
        o.colour = colour;
        o.lit = lit;
        o.world_from_model = placed * world;
        out.push_back(o);
    };
    if (s.radial_copies != 0) {  // the axis: a thin rod through the centre, a little longer than the box
        const int a = s.radial_axis;
        const double len = 1.1 * bounds_.size()[a], r = 0.004 * glm::length(bounds_.size());
        Vec3 start = centre_;
        start[a] -= 0.5 * len;
        // unit_cylinder runs along +z: turn +z onto the axis.
        glm::dmat4 turn(1.0);
        if (a == 0) turn = glm::rotate(glm::dmat4(1.0), 0.5 * glm::pi<double>(), Vec3(0.0, 1.0, 0.0));
        if (a == 1) turn = glm::rotate(glm::dmat4(1.0), -0.5 * glm::pi<double>(), Vec3(1.0, 0.0, 0.0));
        const glm::dmat4 m = glm::translate(glm::dmat4(1.0), start) * turn * glm::scale(glm::dmat4(1.0), Vec3(r, r, len));
        add(cylinder_, glm::mat4(m), glm::vec4(kSymmetryPlaneColour.r, kSymmetryPlaneColour.g, kSymmetryPlaneColour.b, 0.4f),
            false);
    }
    for (int a = 0; a < 3; ++a)
        if (s.mirrors & (1u << a)) add(planes_[a], glm::mat4(1.0f), kSymmetryPlaneColour, false);
    const std::vector<compute::SymmetryTransform> ts = compute::symmetry_transforms(s);
    for (std::size_t k = 1; k < ts.size(); ++k) {
        const Pose p = compute::symmetric_pose(ts[k], centre_, world_from_model.inverse() * tool_pose);
        if (tool.kind == ToolKind::kFlatEnd && tool.length_m > 0.0) {
            // As the renderer draws the tool: unit_cylinder's +z onto the tool frame's +y (the shank).
            const glm::dmat4 shape = glm::rotate(glm::dmat4(1.0), -0.5 * glm::pi<double>(), Vec3(1.0, 0.0, 0.0)) *
                                     glm::scale(glm::dmat4(1.0), Vec3(tool.radius_m, tool.radius_m, tool.length_m));
            add(cylinder_, glm::mat4(p.matrix()) * glm::mat4(shape), kGhostToolColour, true);
        } else if (tool.kind == ToolKind::kMesh && !mesh_.triangles.empty()) {
            add(ts[k].mirrored ? mirrored_mesh_ : mesh_, glm::mat4(p.matrix()), kGhostToolColour, true);
        } else {
            add(sphere_, glm::mat4(glm::translate(glm::dmat4(1.0), p.position) *
                                   glm::scale(glm::dmat4(1.0), Vec3(tool.radius_m))),
                kGhostToolColour, true);
        }
    }
}

}  // namespace tridex::app
