// renderer/scene/overlay_content.hpp - the lines of the 2D overlay: rates, frame time, tiles per eye.
#pragma once

#include <array>
#include <string>

#include "renderer/timing/frame_stats.hpp"

namespace tridex::renderer {

/// The numbers the overlay shows. Negative rates / times are unknown and shown as "--".
struct OverlayNumbers {
    double haptic_rate_hz = -1.0;  ///< haptic loop rate, Hz
    double sculpt_rate_hz = -1.0;  ///< sculpt (Boolean + contour) update rate, Hz
    double frame_ms = -1.0;        ///< frame time, ms
    bool has_tiles = false;        ///< the scene is drawn as tiles (show the per-eye counts)
    std::array<EyeTileCounts, 2> tiles{};  ///< tiles drawn / skipped per eye
    std::string status;            ///< further lines from the app (e.g. what was saved, what is not), '\n' between
};

/// The overlay text, lines separated by '\n':
///   "haptic 1000 Hz  sculpt 60 Hz"
///   "frame 12.3 ms"
///   "tiles L 120 drawn 30 skipped"   (only with has_tiles)
///   "tiles R 118 drawn 32 skipped"
///   then `status`, when not empty.
/// Rates are rounded to whole Hz, the frame time to 0.1 ms; NaN counts as unknown.
std::string overlay_content(const OverlayNumbers& numbers);

}  // namespace tridex::renderer
