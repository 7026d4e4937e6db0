// app/session/shared/presence_view.hpp - the other sites' tools in a shared session, drawn in each person's colour.
#pragma once

#include <vector>

#include "app/session/runtime/session_companion.hpp"
#include "app/session/shared/shared_message.hpp"
#include "core/tri_mesh.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

/// This site's presence in the frame just shown: its tool's pose and radius, with `site`, `name` and `colour`.
PresenceMessage presence_of(const FrameShown& shown, std::uint8_t site, const std::string& name, const Vec3& colour);

/// Draws each other site's tool as a ball of its radius in that person's colour (drawn, never felt: each site feels
/// only its own tool's contact). Keeps the ball's mesh, so it must outlive the frames that draw it.
class PresenceView {
public:
    PresenceView();
    /// Appends a ball for each site in `others` that is not gone, has a finite pose and a tool radius > 0.
    void append(const std::vector<PresenceMessage>& others, std::vector<renderer::SceneObject>& out) const;

private:
    TriMesh ball_;  // the unit sphere
};

}  // namespace tridex::app
