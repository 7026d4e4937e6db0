// app/session/shared/presence_view.cpp - the other sites' tools as coloured balls.
#include "app/session/shared/presence_view.hpp"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "renderer/scene/plane_marks.hpp"
#include "renderer/scene/primitive_meshes.hpp"

namespace tridex::app {

namespace {
float linear_of(double srgb) {  // the sRGB transfer function's inverse (IEC 61966-2-1)
    return static_cast<float>(srgb <= 0.04045 ? srgb / 12.92 : std::pow((srgb + 0.055) / 1.055, 2.4));
}
}  // namespace

PresenceMessage presence_of(const FrameShown& shown, std::uint8_t site, const std::string& name, const Vec3& colour) {
    PresenceMessage p;
    p.site = site;
    p.name = name;
    p.colour = colour;
    p.tool = Pose{is_finite(shown.proxy_m) ? shown.proxy_m : shown.tool_m, shown.tool_orientation};  // as it touches
    p.tool_radius_m = shown.tool.radius_m;
    return p;
}

PresenceView::PresenceView() : ball_(renderer::unit_sphere(12, 24)) {}

void PresenceView::append(const std::vector<PresenceMessage>& others, std::vector<renderer::SceneObject>& out) const {
    for (const PresenceMessage& p : others) {
        if (p.gone || !is_finite(p.tool.position) || !(p.tool_radius_m > 0.0)) continue;
        renderer::SceneObject o;
        o.mesh = &ball_;
        o.colour = glm::vec4(linear_of(p.colour.x), linear_of(p.colour.y), linear_of(p.colour.z), 0.85f);
        o.world_from_model = glm::mat4(glm::translate(glm::dmat4(1.0), p.tool.position) *
                                       glm::scale(glm::dmat4(1.0), Vec3(p.tool_radius_m)));
        out.push_back(o);
        Label& label = labels_[p.site];
        if (label.name != p.name || label.mesh.triangles.empty()) {
            label.name = p.name;
            label.mesh = TriMesh{};
            renderer::add_plane_text(label.mesh, renderer::PlaneFrame{}, p.name, 0.0, kLabelHeightM, kLabelHeightM, 0.5, 0.0);
        }
        if (label.mesh.triangles.empty()) continue;
        renderer::SceneObject name;
        name.mesh = &label.mesh;
        name.colour = glm::vec4(o.colour.r, o.colour.g, o.colour.b, 1.0f);
        name.lit = false;
        name.world_from_model = glm::mat4(glm::translate(
            glm::dmat4(1.0), p.tool.position + Vec3(0.0, p.tool_radius_m + 0.5 * kLabelHeightM, 0.0)));
        out.push_back(name);
    }
}

}  // namespace tridex::app
