// app/session/view/elastic_view.hpp - a run's elastic (and rigid) objects as the render thread draws them: each frame, the elastic
// ones dented under the tool's contact points, and what the report says of their deformation.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "app/scene/elastic_scene.hpp"
#include "core/tri_mesh.hpp"
#include "haptics/haptic_loop.hpp"
#include "haptics/tool_points.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

/// The drawn surfaces of a scene's spheres (RunScene::objects). The haptic loop feels the same spheres through their
/// undeformed surfaces (HapticLoopConfig::elastic_objects); this recomputes the contacts from the tool pose the loop
/// publishes (haptics::elastic_contacts, the same points, scaled when the tool is resized), so the dent drawn is the
/// one felt (Popescu, Burdea, Bouzit 3.3: displacement d_m * (1 - (x/r)^2) within the radius of influence r, the
/// largest winning; none once the tool lets go). Render thread only.
class ElasticView {
public:
    /// `objects`: the scene's spheres (kept by reference: must outlive the view); `points`: the loop's contact points
    /// for a tool of radius `tool_radius_m` (> 0, m), as configured (HapticLoop::config().tool_points). Builds each
    /// sphere's reference mesh (an icosphere, about 10k vertices). Throws tridex::Error when tool_radius_m is not > 0.
    ElasticView(const std::vector<SceneSphere>& objects, const haptics::ToolPoints& points, double tool_radius_m);

    /// Dents the elastic objects under the tool of `view` (nothing before the loop's first tick) and returns every
    /// object to draw in its colour (valid until the next call).
    const std::vector<renderer::SceneObject>& frame(const haptics::LoopView& view);

    /// Largest vertex displacement of any drawn surface so far, m.
    double max_displacement_m() const { return max_displacement_m_; }
    /// Largest vertex displacement in the last frame drawn, m (0 once the tool has let go: it springs back).
    double residual_displacement_m() const { return residual_m_; }

    /// report.json `deformation`: {max_displacement_m, residual_displacement_m, objects: [{name, elastic,
    /// frames_pressed, max_displacement_m}]}.
    nlohmann::json report_json() const;

private:
    const std::vector<SceneSphere>& objects_;
    haptics::ToolPoints points_;
    double tool_radius_m_;
    std::vector<TriMesh> reference_, drawn_;
    std::vector<renderer::SceneObject> scene_;
    std::vector<double> object_max_m_;
    std::vector<std::size_t> frames_pressed_;
    double max_displacement_m_ = 0.0, residual_m_ = 0.0;
};

}  // namespace tridex::app
