// app/session/cluster/cluster_replica.cpp - the replicated model: records applied, tiles contoured, viewports framed.
#include "app/session/cluster/cluster_replica.hpp"

#include <cmath>

#include "app/scene/session_spec.hpp"
#include "app/session/view/run_view.hpp"
#include "compute/model/model_digest.hpp"
#include "renderer/camera/off_axis.hpp"
#include "renderer/camera/scene_navigation.hpp"

namespace tridex::app {

ClusterReplica::ClusterReplica(const std::string& spec_json) {
    SessionSpec spec = spec_from_json(spec_json, "the session spec from rank 0");
    wp_ = prepare_session_workpiece(spec);
    applier_ = std::make_unique<compute::JournalApplier>(wp_.model, replay_settings(spec));
    contourer_ = std::make_unique<compute::Contourer>(wp_.model);
    contour();
}

ClusterReplica::~ClusterReplica() = default;

std::uint64_t ClusterReplica::digest() const { return compute::model_digest(wp_.model); }

std::optional<std::uint64_t> ClusterReplica::apply(const FrameMessage& m) {
    const std::span<const compute::JournalRecord> all(m.records);
    if (!m.check_digest) {
        applier_->apply(all);
        return std::nullopt;
    }
    applier_->apply(all.first(m.check_after));
    const std::uint64_t mine = digest();
    applier_->apply(all.subspan(m.check_after));
    if (mine != *m.check_digest) return mine;
    return std::nullopt;
}

void ClusterReplica::contour() {
    contourer_->update(wp_.model);
    tiles_.refresh(*contourer_);
    tile_view_of(tiles_.tiles(), tiles_.groups(), false, tile_view_);
}

renderer::SceneView ClusterReplica::view(const FrameMessage& m) const {
    renderer::SceneView v;
    v.tiles = tile_view_.tiles;
    v.lod = false;
    v.show_workspace = false;
    v.tool_shape = m.tool;
    v.tool_radius_m = m.show_tool ? m.tool.radius_m : 0.0;
    v.tool_centre_m = m.tool_m;
    v.tool_orientation = m.tool_orientation;
    v.occlusion_strength = m.ao;
    return v;
}

renderer::StereoCamera ClusterReplica::camera(const ClusterViewport& vp, const FrameMessage& m) {
    const renderer::SceneNavigation nav(m.nav_pose, m.nav_scale, std::min(1e-3, m.nav_scale), std::max(1e3, m.nav_scale));
    Pose head = m.head;
    double separation = m.eye_separation_m;
    if (vp.eye != ViewportEye::kBoth) {
        // One eye of a passive pair: a mono view from that eye.
        head.position = renderer::eye_positions(head, separation)[vp.eye == ViewportEye::kLeft ? 0 : 1];
        separation = 0.0;
    }
    const RunCamera c = navigated_camera(vp.screen, head, separation, nav);
    return renderer::StereoCamera{c.screen, c.head, c.eye_separation_m, c.near_m, c.far_m};
}

void ClusterReplica::diverge() {
    for (compute::RaySet& set : wp_.model.sets)
        for (std::vector<compute::Interval>& ray : set.rays)
            if (!ray.empty()) {
                ray[0].exit = std::nextafter(ray[0].exit, ray[0].exit + 1.0f);
                return;
            }
}

const compute::JournalApplyStats& ClusterReplica::applied() const { return applier_->stats(); }

}  // namespace tridex::app
