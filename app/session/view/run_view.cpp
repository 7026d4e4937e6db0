// app/session/view/run_view.cpp - scene view and navigated camera of one frame.
#include "app/session/view/run_view.hpp"

#include <cmath>

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
    // As in Peng et al. (4.1): the workspace is drawn while its button is held (modelling paused), not always.
    s.show_workspace = view.tick > 0 && view.modelling_paused;
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

void add_run_items(renderer::SceneView& s, const haptics::LoopView& view, double proxy_radius_m,
                   double force_m_per_newton, const RunOverlay& o) {
    if (view.tick > 0) {
        s.proxy_m = view.proxy_m;
        s.proxy_radius_m = proxy_radius_m;
        s.force_N = view.force_n;
        s.force_m_per_newton = force_m_per_newton;
    }
    s.show_overlay = true;
    s.haptic_rate_hz = o.haptic_rate_hz;
    s.sculpt_rate_hz = o.sculpt_rate_hz;
    s.frame_time_ms = o.frame_time_ms;
    s.overlay_status = o.status;
    s.overlay_tile_counts = o.tile_counts;
}

void RateMeter::add(double t_s, std::uint64_t count) {
    if (!samples_.empty() && (t_s < samples_.back().first || count < samples_.back().second)) samples_.clear();
    if (!samples_.empty() && t_s == samples_.back().first)
        samples_.back().second = count;
    else
        samples_.emplace_back(t_s, count);
    // Keep one sample at or before the window's start, so the span covers the whole window once it can.
    while (samples_.size() > 2 && samples_[1].first <= t_s - window_s_) samples_.pop_front();
}

double RateMeter::rate_hz() const {
    if (samples_.size() < 2) return -1.0;
    const double dt = samples_.back().first - samples_.front().first;
    if (dt <= 0.0) return -1.0;
    return static_cast<double>(samples_.back().second - samples_.front().second) / dt;
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

bool eyes_see_screen(const RunCamera& c) {
    const Pose& h = c.head;
    const bool finite = std::isfinite(h.position.x) && std::isfinite(h.position.y) && std::isfinite(h.position.z) &&
                        std::isfinite(h.orientation.w) && std::isfinite(h.orientation.x) &&
                        std::isfinite(h.orientation.y) && std::isfinite(h.orientation.z) &&
                        std::isfinite(c.eye_separation_m);
    if (!finite) return false;
    const Vec3 right = c.screen.lower_right - c.screen.lower_left, up = c.screen.upper_left - c.screen.lower_left;
    const Vec3 n = glm::cross(right, up);
    const double len = glm::length(n);
    if (!(len > 0.0)) return false;
    constexpr double kMinEyeDistanceM = 1e-4;
    for (const Vec3& eye : renderer::eye_positions(h, c.eye_separation_m))
        if (!(glm::dot(eye - c.screen.lower_left, n / len) > kMinEyeDistanceM)) return false;
    return true;
}

}  // namespace tridex::app
