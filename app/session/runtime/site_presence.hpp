// app/session/runtime/site_presence.hpp - where another site of a shared session is: its person's tool and, when
// tracked, head, in the scene frame, for this site (and a cluster wall's render ranks) to draw.
#pragma once

#include <cstdint>
#include <string>

#include "core/pose.hpp"

namespace tridex::app {

/// The radius of a person's head as drawn at the other sites, world m.
inline constexpr double kHeadRadiusM = 0.09;

/// A site's presence (sent unreliably in a shared session, newest wins; carried to a cluster's render ranks in each
/// frame message). Positions in the shared workpiece's model frame (its lattice's: the scene frame with the site's
/// workpiece pose undone), so each site draws the others where they are relative to the model however each site
/// placed it (PresenceView::append maps them through the drawing site's pose).
struct SitePresence {
    std::uint8_t site = 0;   ///< 0 the host, 1..kMaxSites-1 the joiners
    bool gone = false;       ///< the site left: stop drawing it
    std::string name;        ///< the person (0..64 bytes, no control characters)
    Vec3 colour{1.0};        ///< sRGB 0..1
    Pose tool;               ///< where the tool touches (its proxy; its centre when free), model m
    double tool_radius_m = 0.0;  ///< scene m, [0, 1]
    /// The person's head follows a tracker (or a script): `head` is where it is and it is drawn for the others.
    bool head_tracked = false;
    Pose head;               ///< the head (between the eyes; -z looks ahead, +y up), model m; meaningful when tracked
    double head_size_m = 0.0;    ///< a real head's radius in scene m (kHeadRadiusM / the site's scene scale), (0, 100]
};

}  // namespace tridex::app
