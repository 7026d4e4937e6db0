// app/input/cursor_script.hpp - a scene's scripted mouse cursor, for mouse-stylus sessions without a window.
#pragma once

#include <cstdint>
#include <vector>

namespace tridex::app {

/// Mouse button bits of a scripted cursor point.
namespace cursor_buttons {
inline constexpr std::uint32_t kLeft = 1u;   ///< the left button (engage the tool)
inline constexpr std::uint32_t kRight = 2u;  ///< the right button (the stylus button)
}  // namespace cursor_buttons

/// One point of a scripted cursor: where the cursor is (pixels from the image's top-left) and which buttons are
/// held from this device time on.
struct CursorPoint {
    double t_s = 0.0;           ///< device time, s (the haptic loop's clock)
    double x_px = 0.0;          ///< cursor x, pixels
    double y_px = 0.0;          ///< cursor y, pixels
    std::uint32_t buttons = 0;  ///< cursor_buttons bits held from t_s until the next point
    double wheel = 0.0;         ///< wheel steps turned once when the script reaches t_s (MouseStylus::wheel: + = deeper)
};

/// A cursor path in device time: the position is interpolated linearly between points, the buttons are those
/// of the last point at or before t. Points are in non-decreasing time order (the scene reader checks it).
struct CursorScript {
    std::vector<CursorPoint> points;

    /// True when there are no points.
    bool empty() const { return points.empty(); }
    /// The time of the last point, s (0 when empty).
    double end_s() const { return points.empty() ? 0.0 : points.back().t_s; }
    /// The cursor at device time t_s: before the first point, the first point (buttons up); after the last,
    /// the last. Never throws; an empty script gives a default point.
    CursorPoint at(double t_s) const;
};

}  // namespace tridex::app
