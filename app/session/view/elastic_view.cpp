// app/session/view/elastic_view.cpp - drawing a run's elastic objects dented under the tool.
#include "app/session/view/elastic_view.hpp"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/primitives.hpp"
#include "haptics/elastic_object.hpp"

namespace tridex::app {

namespace {
constexpr int kSubdivisions = 5;  // about 10k vertices: 1 mm apart on a 3 cm ball
}  // namespace

ElasticView::ElasticView(const std::vector<SceneSphere>& objects, const haptics::ToolPoints& points,
                         double tool_radius_m)
    : objects_(objects), points_(points), tool_radius_m_(tool_radius_m) {
    if (!(tool_radius_m > 0.0)) throw Error("ElasticView: the tool radius must be > 0");
    for (const SceneSphere& o : objects_) {
        reference_.push_back(icosphere_mesh(o.sphere.centre_m, o.sphere.radius_m, kSubdivisions));
        drawn_.push_back(reference_.back());
    }
    object_max_m_.assign(objects_.size(), 0.0);
    frames_pressed_.assign(objects_.size(), 0);
}

const std::vector<renderer::SceneObject>& ElasticView::frame(const haptics::LoopView& view) {
    // The loop's points for the tool in use now ([ and ] resize it about its centre).
    const haptics::ToolPoints pts = points_.scaled(view.tool.radius_m > 0.0 ? view.tool.radius_m / tool_radius_m_ : 1.0);
    residual_m_ = 0.0;
    scene_.clear();
    for (std::size_t i = 0; i < objects_.size(); ++i) {
        const SceneSphere& o = objects_[i];
        const haptics::ElasticContacts c =
            view.tick > 0 ? haptics::elastic_contacts(o.sphere, pts, view.tool_world) : haptics::ElasticContacts{};
        // A rigid object is felt the same way but drawn as it is.
        haptics::deform_elastic_mesh(reference_[i], o.elastic ? c : haptics::ElasticContacts{}, o.sphere.influence_m,
                                     drawn_[i]);
        const double d =
            c.count > 0 && o.elastic ? haptics::max_vertex_displacement_m(reference_[i], drawn_[i]) : 0.0;
        if (c.count > 0) ++frames_pressed_[i];
        object_max_m_[i] = std::max(object_max_m_[i], d);
        max_displacement_m_ = std::max(max_displacement_m_, d);
        residual_m_ = std::max(residual_m_, d);
        scene_.push_back({&drawn_[i], glm::vec4(glm::vec3(o.colour), static_cast<float>(o.alpha))});
    }
    return scene_;
}

nlohmann::json ElasticView::report_json() const {
    nlohmann::json objects = nlohmann::json::array();
    for (std::size_t i = 0; i < objects_.size(); ++i)
        objects.push_back({{"name", objects_[i].name},
                           {"elastic", objects_[i].elastic},
                           {"frames_pressed", frames_pressed_[i]},
                           {"max_displacement_m", object_max_m_[i]}});
    return {{"max_displacement_m", max_displacement_m_},
            {"residual_displacement_m", residual_m_},
            {"objects", objects}};
}

}  // namespace tridex::app
