// app/input/cursor_script.cpp - linear interpolation of a scripted cursor.
#include "app/input/cursor_script.hpp"

#include <algorithm>

namespace tridex::app {

CursorPoint CursorScript::at(double t_s) const {
    if (points.empty()) return {};
    if (!(t_s >= points.front().t_s)) {  // before the start (or NaN): the first position, nothing held
        CursorPoint p = points.front();
        p.t_s = t_s;
        p.buttons = 0;
        return p;
    }
    const auto it = std::upper_bound(points.begin(), points.end(), t_s,
                                     [](double t, const CursorPoint& p) { return t < p.t_s; });
    const CursorPoint& a = *(it - 1);
    if (it == points.end()) return a;
    const CursorPoint& b = *it;
    const double span = b.t_s - a.t_s;
    const double u = span > 0.0 ? (t_s - a.t_s) / span : 1.0;
    return CursorPoint{t_s, a.x_px + u * (b.x_px - a.x_px), a.y_px + u * (b.y_px - a.y_px), a.buttons};
}

}  // namespace tridex::app
