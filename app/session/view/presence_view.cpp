// app/session/view/presence_view.cpp - the other sites' tools and heads in their colours.
#include "app/session/view/presence_view.hpp"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "renderer/scene/plane_marks.hpp"
#include "renderer/scene/primitive_meshes.hpp"

namespace tridex::app {

namespace {
float linear_of(double srgb) {  // the sRGB transfer function's inverse (IEC 61966-2-1)
    return static_cast<float>(srgb <= 0.04045 ? srgb / 12.92 : std::pow((srgb + 0.055) / 1.055, 2.4));
}
}  // namespace

SitePresence presence_of(const FrameShown& shown, std::uint8_t site, const std::string& name, const Vec3& colour) {
    SitePresence p;
    p.site = site;
    p.name = name;
    p.colour = colour;
    // Into the workpiece's model frame: the others draw it through their own pose of the shared model.
    const Pose model_from_scene = shown.workpiece_pose.inverse();
    p.tool = model_from_scene *
             Pose{is_finite(shown.proxy_m) ? shown.proxy_m : shown.tool_m, shown.tool_orientation};  // as it touches
    p.tool_radius_m = shown.tool.radius_m;
    if (shown.head_tracked && shown.nav && is_finite(shown.head.position)) {
        // The head is in the room; the others see it where it stands relative to the workpiece.
        p.head_tracked = true;
        const Pose head_scene{shown.nav->to_scene(shown.head.position),
                              glm::normalize(glm::conjugate(shown.nav->pose().orientation) * shown.head.orientation)};
        p.head = model_from_scene * head_scene;
        p.head_size_m = kHeadRadiusM / shown.nav->scale();
    }
    return p;
}

PresenceView::PresenceView() : ball_(renderer::unit_sphere(12, 24)) {}

const TriMesh* PresenceView::label_of(const SitePresence& p) const {
    Label& label = labels_[p.site];
    if (label.name != p.name || label.mesh.triangles.empty()) {
        label.name = p.name;
        label.mesh = TriMesh{};
        renderer::add_plane_text(label.mesh, renderer::PlaneFrame{}, p.name, 0.0, kLabelHeightM, kLabelHeightM, 0.5, 0.0);
    }
    return label.mesh.triangles.empty() ? nullptr : &label.mesh;
}

void PresenceView::append(const std::vector<SitePresence>& others, std::vector<renderer::SceneObject>& out,
                          const Vec3& eye_m, const Pose& workpiece_pose) const {
    for (const SitePresence& in_model : others) {
        if (in_model.gone) continue;
        SitePresence p = in_model;  // into this site's scene: through its pose of the shared workpiece
        p.tool = workpiece_pose * in_model.tool;
        p.head = workpiece_pose * in_model.head;
        const glm::vec4 colour(linear_of(p.colour.x), linear_of(p.colour.y), linear_of(p.colour.z), 0.85f);
        const TriMesh* label = label_of(p);
        const auto add_label = [&](const Vec3& at, double scale) {
            if (!label) return;
            renderer::SceneObject name;
            name.mesh = label;
            name.colour = glm::vec4(colour.r, colour.g, colour.b, 1.0f);
            name.lit = false;
            // Upright, turned about +y so that the text's front (+z) faces the eye.
            const Vec3 to_eye = eye_m - at;
            const double yaw = is_finite(eye_m) && (to_eye.x != 0.0 || to_eye.z != 0.0) ? std::atan2(to_eye.x, to_eye.z) : 0.0;
            name.world_from_model = glm::mat4(glm::translate(glm::dmat4(1.0), at) *
                                              glm::rotate(glm::dmat4(1.0), yaw, Vec3(0.0, 1.0, 0.0)) *
                                              glm::scale(glm::dmat4(1.0), Vec3(scale)));
            out.push_back(name);
        };
        if (is_finite(p.tool.position) && p.tool_radius_m > 0.0) {
            renderer::SceneObject o;
            o.mesh = &ball_;
            o.colour = colour;
            o.world_from_model = glm::mat4(glm::translate(glm::dmat4(1.0), p.tool.position) *
                                           glm::scale(glm::dmat4(1.0), Vec3(p.tool_radius_m)));
            out.push_back(o);
            add_label(p.tool.position + Vec3(0.0, p.tool_radius_m + 0.5 * kLabelHeightM, 0.0), 1.0);
        }
        if (p.head_tracked && is_finite(p.head.position) && p.head_size_m > 0.0) {
            const glm::dmat4 head_from = glm::translate(glm::dmat4(1.0), p.head.position) *
                                         glm::mat4_cast(glm::normalize(p.head.orientation)) *
                                         glm::scale(glm::dmat4(1.0), Vec3(p.head_size_m));
            renderer::SceneObject head;  // a head, a little narrower than deep and tall
            head.mesh = &ball_;
            head.colour = colour;
            head.world_from_model = glm::mat4(head_from * glm::scale(glm::dmat4(1.0), Vec3(0.8, 1.0, 0.95)));
            out.push_back(head);
            renderer::SceneObject glasses = head;  // dark glasses at its front (-z looks ahead): where it looks
            glasses.colour = glm::vec4(0.03f, 0.03f, 0.04f, 1.0f);
            glasses.world_from_model = glm::mat4(head_from * glm::translate(glm::dmat4(1.0), Vec3(0.0, 0.12, -0.78)) *
                                                 glm::scale(glm::dmat4(1.0), Vec3(0.78, 0.24, 0.3)));
            out.push_back(glasses);
            const double name_scale = 0.45 * p.head_size_m / kLabelHeightM;  // letters a quarter of the head tall
            add_label(p.head.position + Vec3(0.0, 1.1 * p.head_size_m + 0.5 * name_scale * kLabelHeightM, 0.0), name_scale);
        }
    }
}

}  // namespace tridex::app
