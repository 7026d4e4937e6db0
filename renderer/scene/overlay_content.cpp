// renderer/scene/overlay_content.cpp - formatting the overlay lines.
#include "renderer/scene/overlay_content.hpp"

#include <cmath>
#include <cstdio>

namespace tridex::renderer {
namespace {

std::string number(double value, const char* format) {
    if (!(value >= 0.0) || !std::isfinite(value)) return "--";
    char buf[64];
    std::snprintf(buf, sizeof buf, format, value);
    return buf;
}

}  // namespace

std::string overlay_content(const OverlayNumbers& n) {
    std::string s = "haptic " + number(n.haptic_rate_hz, "%.0f") + " Hz  sculpt " + number(n.sculpt_rate_hz, "%.0f") +
                    " Hz\nframe " + number(n.frame_ms, "%.1f") + " ms";
    if (n.has_tiles)
        for (int e = 0; e < 2; ++e)
            s += std::string("\ntiles ") + (e == 0 ? "L " : "R ") + std::to_string(n.tiles[e].drawn) + " drawn " +
                 std::to_string(n.tiles[e].skipped) + " skipped";
    if (!n.status.empty()) s += "\n" + n.status;
    return s;
}

}  // namespace tridex::renderer
