// haptics/multipoint.cpp - per-point god-objects, force sum and torque about the tool centre.
#include "haptics/multipoint.hpp"

#include <cmath>

#include "haptics/forces/interaction_mesh.hpp"

namespace tridex::haptics {

namespace {

ContactParams point_params(ContactParams params, const ToolPoints& points) {
    params.tool_radius_m = points.radius_m;
    return params;
}

bool finite_pose(const Pose& p) {
    return is_finite(p.position) && std::isfinite(p.orientation.w) && std::isfinite(p.orientation.x) &&
           std::isfinite(p.orientation.y) && std::isfinite(p.orientation.z);
}

}  // namespace

MultiPointRenderer::MultiPointRenderer(const ToolPoints& points, const ContactParams& params, MultiPointMode mode)
    : points_(points), mode_(mode), stiffness_n_per_m_(params.stiffness_n_per_m) {
    validate(points_, mode_ == MultiPointMode::kInteractionMesh);
    const ContactParams p = point_params(params, points_);
    proxies_.reserve(static_cast<std::size_t>(points_.count));
    for (int i = 0; i < points_.count; ++i) proxies_.emplace_back(p);  // GodObject checks the parameters
}

void MultiPointRenderer::reset() {
    for (GodObject& g : proxies_) g.reset();
    result_ = MultiPointResult{};
}

bool MultiPointRenderer::set_points(const ToolPoints& points) {
    if (points.count != points_.count || !(std::isfinite(points.radius_m) && points.radius_m >= 0.0)) return false;
    for (int i = 0; i < points.count; ++i)
        if (!is_finite(points.local_m[static_cast<std::size_t>(i)])) return false;
    points_ = points;
    for (GodObject& g : proxies_) g.set_tool_radius(points_.radius_m);
    result_ = MultiPointResult{};
    return true;
}

const MultiPointResult& MultiPointRenderer::update(const ActiveSurface& surface, const Pose& tool, double dt_s) {
    if (!finite_pose(tool)) {
        reset();
        return result_;
    }
    MultiPointResult& r = result_;
    r.wrench = Wrench{};
    r.points = points_.count;
    r.in_contact = 0;
    r.cos_q = 1.0;
    const bool mesh = mode_ == MultiPointMode::kInteractionMesh;
    Vec3 contact_normal(0.0);  // mesh: sum of d_m * n_m over the points in contact
    for (int i = 0; i < points_.count; ++i) {
        const Vec3 lever = tool.orientation * points_.local_m[i];  // r_i = R*T_i, about the tool centre
        const Vec3 world = lever + tool.position;                  // P_i = R*T_i + P_w
        const ContactResult c = proxies_[static_cast<std::size_t>(i)].update(surface, world, dt_s);
        PointState& s = r.point[i];
        s.world_m = world;
        s.proxy_m = c.proxy_m;
        s.normal = c.normal;
        s.depth_m = c.depth_m;
        s.contact = c.contact;
        s.hip_inside = c.hip_inside;
        if (mesh) {
            const Vec3 inward = -(tool.orientation * points_.normal[i]);
            s.force_n = c.contact ? mesh_point_force(stiffness_n_per_m_, c.depth_m, inward) : Vec3(0.0);
            if (c.contact) contact_normal += c.depth_m * c.normal;
        } else {
            s.force_n = c.force_n;
        }
        if (c.contact) ++r.in_contact;
        r.wrench.force_n += s.force_n;
        r.wrench.torque_nm += glm::cross(lever, s.force_n);
    }
    if (mesh) {
        const MeshForce m = display_mesh_force(r.wrench.force_n, contact_normal);
        r.cos_q = m.cos_q;
        r.wrench.force_n = m.displayed_n;
        r.wrench.torque_nm *= m.gain;
    }
    return r;
}

}  // namespace tridex::haptics
