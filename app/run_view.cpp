// app/run_view.cpp - scene view and navigated camera of one frame.
#include "app/run_view.hpp"

namespace tridex::app {

Aabb enclosing_box(const Pose& box, const Vec3& half_m) {
    Aabb out;
    for (int c = 0; c < 8; ++c) {
        const Vec3 corner((c & 1) ? half_m.x : -half_m.x, (c & 2) ? half_m.y : -half_m.y, (c & 4) ? half_m.z : -half_m.z);
        out.add(box.apply(corner));
    }
    return out;
}

renderer::SceneView scene_view_from(const haptics::LoopView& view, const TriMesh* mesh, double tool_radius_m,
                                    const Vec3& fallback_tool_m, const Aabb& fallback_box_m) {
    renderer::SceneView s;
    s.workpiece = mesh;
    s.tool_radius_m = tool_radius_m;
    s.show_workspace = true;
    if (view.tick == 0) {
        s.tool_centre_m = fallback_tool_m;
        s.workspace_m = fallback_box_m;
        return s;
    }
    s.tool_centre_m = view.tool_world.position;
    s.workspace_m = enclosing_box(view.box, view.box_half_extents_m);
    if (view.bubble_radius_m > 0.0) {
        s.bubble_centre_m = view.bubble_centre_m;
        s.bubble_radius_m = view.bubble_radius_m;
    }
    return s;
}

RunCamera navigated_camera(const renderer::Screen& screen, const Pose& head, double eye_separation_m,
                           const renderer::SceneNavigation& nav, double near_m, double far_m) {
    const double s = nav.scale();
    RunCamera c;
    c.screen = renderer::Screen{nav.to_scene(screen.lower_left), nav.to_scene(screen.lower_right),
                                nav.to_scene(screen.upper_left)};
    c.head.position = nav.to_scene(head.position);
    c.head.orientation = glm::normalize(glm::conjugate(nav.pose().orientation) * head.orientation);
    c.eye_separation_m = eye_separation_m / s;
    c.near_m = near_m / s;
    c.far_m = far_m / s;
    return c;
}

}  // namespace tridex::app
