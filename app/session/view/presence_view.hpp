// app/session/view/presence_view.hpp - the other sites of a shared session (their tools and tracked heads), drawn in
// each person's colour, at a site and on a cluster wall's render ranks.
#pragma once

#include <limits>
#include <map>
#include <string>
#include <vector>

#include "app/session/runtime/session_companion.hpp"
#include "app/session/runtime/site_presence.hpp"
#include "core/tri_mesh.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

/// This site's presence in the frame just shown: its tool where it touches (the proxy; the tool centre when free), its
/// orientation and radius, with `site`, `name` and `colour`; when shown.head_tracked (and shown.nav is set), its head
/// mapped into the scene frame (kHeadRadiusM / the scene scale in size). Poses in the workpiece's model frame
/// (shown.workpiece_pose undone; SitePresence).
SitePresence presence_of(const FrameShown& shown, std::uint8_t site, const std::string& name, const Vec3& colour);

/// Draws each other site's tool as a ball of its radius in that person's colour, their name above it (in the plane of
/// the screen, or facing the viewer, kLabelHeightM tall), drawn, never felt: each site feels only its own tool's contact. A site whose head
/// is tracked also shows its head (an ellipsoid of the head's size in the same colour, dark glasses at its front
/// showing where it looks) with the name above it. The others come in the shared workpiece's model frame and are drawn
/// through this site's pose of it, so each site sees the others where they are relative to the workpiece whatever
/// each navigated or placed. Keeps the meshes, so it must outlive the frames that draw them; one thread calls
/// append().
class PresenceView {
public:
    /// Height of a name's letters, m.
    static constexpr double kLabelHeightM = 0.008;
    PresenceView();
    /// Appends, for each site in `others` (model frame) that is not gone, placed by `workpiece_pose` (this site's
    /// pose of the workpiece: model -> scene): a ball and a name when its tool has a finite position and a radius > 0;
    /// a head (two objects) and a name when its head is tracked, finite and of a size > 0. Each name stands upright and
    /// turns about the vertical to face `eye_m` (the viewer's eye, scene m); a non-finite eye leaves the names in the
    /// plane of the screen.
    void append(const std::vector<SitePresence>& others, std::vector<renderer::SceneObject>& out,
                const Vec3& eye_m = Vec3(std::numeric_limits<double>::quiet_NaN()),
                const Pose& workpiece_pose = Pose{}) const;

private:
    const TriMesh* label_of(const SitePresence& p) const;  // its name's mesh (null for an empty name)
    TriMesh ball_;  // the unit sphere
    struct Label {
        std::string name;
        TriMesh mesh;  // the name on the xy plane, centred on x = 0, its top at y = kLabelHeightM
    };
    mutable std::map<std::uint8_t, Label> labels_;  // by site, rebuilt when the name changes
};

}  // namespace tridex::app
