// app/scene/test_pattern.cpp - the wall's test pattern as world-space meshes on (and before) the screen plane.
#include "app/scene/test_pattern.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>

#include "core/error.hpp"
#include "core/primitives.hpp"
#include "renderer/scene/plane_marks.hpp"

namespace tridex::app {

namespace {

// The screen's frame: origin at lower_left, unit right (ex), up (ey) and towards the viewer (n), size in m.
struct Frame : renderer::PlaneFrame {
    double w = 0.0, h = 0.0;
};

using renderer::add_plane_rect;
using renderer::add_plane_text;

// An axis-aligned cube of edge `edge` m about `centre` in the screen's frame (its faces outward).
TriMesh cube_at(const Frame& f, const Vec3& centre, double edge) {
    Aabb unit;
    unit.add(Vec3(-0.5));
    unit.add(Vec3(0.5));
    TriMesh c = box_mesh(unit);
    for (Vec3& p : c.positions) p = centre + edge * (p.x * f.ex + p.y * f.ey + p.z * f.n);
    return c;
}

}  // namespace

std::vector<PatternPiece> wall_test_pattern(const renderer::Screen& screen) {
    if (!is_finite(screen.lower_left) || !is_finite(screen.lower_right) || !is_finite(screen.upper_left))
        throw Error("wall test pattern: the screen corners must be finite");
    Frame f;
    f.o = screen.lower_left;
    f.w = screen.width();
    f.h = screen.height();
    if (!(f.w > 0.0) || !(f.h > 0.0)) throw Error("wall test pattern: the screen has no area");
    f.ex = (screen.lower_right - screen.lower_left) / f.w;
    f.ey = (screen.upper_left - screen.lower_left) / f.h;
    f.n = glm::normalize(glm::cross(f.ex, f.ey));
    constexpr double kMarkOffM = 0.002;  // text and marks in front of the grid
    const double line = std::max(f.h / 400.0, 1e-4), border = f.h / 100.0, text = f.h / 24.0;

    std::vector<PatternPiece> out;
    PatternPiece grid;  // zero parallax: the border and the grid on the screen plane
    grid.colour = glm::vec4(0.75f, 0.75f, 0.75f, 1.0f);
    add_plane_rect(grid.mesh, f, 0.0, 0.0, f.w, border, 0.0);
    add_plane_rect(grid.mesh, f, 0.0, f.h - border, f.w, f.h, 0.0);
    add_plane_rect(grid.mesh, f, 0.0, 0.0, border, f.h, 0.0);
    add_plane_rect(grid.mesh, f, f.w - border, 0.0, f.w, f.h, 0.0);
    const double step = f.h / 8.0;
    for (double v = step; v < f.h - 0.5 * step; v += step) add_plane_rect(grid.mesh, f, 0.0, v - line, f.w, v + line, 0.0);
    for (double u = f.w / 2.0 - step * std::floor(f.w / 2.0 / step); u < f.w; u += step)
        if (u > 0.5 * step) add_plane_rect(grid.mesh, f, u - line, 0.0, u + line, f.h, 0.0);
    out.push_back(std::move(grid));

    PatternPiece corners;  // where the config says the corners are
    corners.colour = glm::vec4(1.0f, 0.85f, 0.2f, 1.0f);
    const double in = 2.0 * border;
    add_plane_text(corners.mesh, f, "LOWER LEFT", in, in + text, text, 0.0, kMarkOffM);
    add_plane_text(corners.mesh, f, "LOWER RIGHT", f.w - in, in + text, text, 1.0, kMarkOffM);
    add_plane_text(corners.mesh, f, "UPPER LEFT", in, f.h - in - step, text, 0.0, kMarkOffM);  // below the overlay
    add_plane_text(corners.mesh, f, "UPPER RIGHT", f.w - in, f.h - in - step, text, 1.0, kMarkOffM);
    add_plane_rect(corners.mesh, f, 0.5 * f.w - 4.0 * line, 0.5 * f.h - 4.0 * step / 8.0, 0.5 * f.w + 4.0 * line,
             0.5 * f.h + 4.0 * step / 8.0, kMarkOffM);  // the centre's cross
    add_plane_rect(corners.mesh, f, 0.5 * f.w - 4.0 * step / 8.0, 0.5 * f.h - 4.0 * line, 0.5 * f.w + 4.0 * step / 8.0,
             0.5 * f.h + 4.0 * line, kMarkOffM);
    out.push_back(std::move(corners));

    PatternPiece left, right;  // one eye each
    left.colour = glm::vec4(1.0f, 0.3f, 0.3f, 1.0f);
    left.eyes = 0b01;
    add_plane_text(left.mesh, f, "LEFT EYE", 0.25 * f.w, 0.5 * f.h + text, 2.0 * text, 0.5, kMarkOffM);
    right.colour = glm::vec4(0.3f, 0.8f, 1.0f, 1.0f);
    right.eyes = 0b10;
    add_plane_text(right.mesh, f, "RIGHT EYE", 0.75 * f.w, 0.5 * f.h + text, 2.0 * text, 0.5, kMarkOffM);
    out.push_back(std::move(left));
    out.push_back(std::move(right));

    const double edge = 0.1 * f.h, depth = 0.2 * f.h;  // depth: green in front, blue behind
    PatternPiece front, behind;
    front.colour = glm::vec4(0.3f, 0.9f, 0.3f, 1.0f);
    front.lit = behind.lit = true;
    front.mesh = cube_at(f, f.at(0.5 * f.w - 0.12 * f.h, 0.3 * f.h, depth), edge);
    behind.colour = glm::vec4(0.3f, 0.4f, 1.0f, 1.0f);
    behind.mesh = cube_at(f, f.at(0.5 * f.w + 0.12 * f.h, 0.3 * f.h, -depth), edge);
    out.push_back(std::move(front));
    out.push_back(std::move(behind));
    return out;
}

}  // namespace tridex::app
