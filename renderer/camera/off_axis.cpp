// renderer/camera/off_axis.cpp - Kooima's generalized perspective projection in Vulkan clip conventions.
#include "renderer/camera/off_axis.hpp"

#include <algorithm>

#include <cmath>

#include "core/error.hpp"
#include "core/units.hpp"

namespace tridex::renderer {

Screen Screen::powerwall() {
    const double hw = 0.5 * units::ft(10.0);   // 1.524 m
    const double hh = 0.5 * units::ft(7.5);    // 1.143 m
    return Screen{Vec3(-hw, -hh, 0.0), Vec3(hw, -hh, 0.0), Vec3(-hw, hh, 0.0)};
}

Screen Screen::desktop_monitor() {
    const double hw = 0.5 * 0.53, hh = 0.5 * 0.30;
    return Screen{Vec3(-hw, -hh, 0.0), Vec3(hw, -hh, 0.0), Vec3(-hw, hh, 0.0)};
}

double Screen::width() const { return glm::length(lower_right - lower_left); }
double Screen::height() const { return glm::length(upper_left - lower_left); }

Screen Screen::fitted_to_aspect(double aspect) const {
    const double w = width(), h = height();
    if (!(std::isfinite(aspect) && aspect > 0.0) || !(w > 0.0) || !(h > 0.0) || !std::isfinite(w * h)) return *this;
    const Vec3 ex = (lower_right - lower_left) / w, ey = (upper_left - lower_left) / h;
    const Vec3 centre = lower_left + 0.5 * (lower_right - lower_left) + 0.5 * (upper_left - lower_left);
    const double nw = std::max(w, h * aspect), nh = nw / aspect;
    Screen s;
    s.lower_left = centre - 0.5 * nw * ex - 0.5 * nh * ey;
    s.lower_right = s.lower_left + nw * ex;
    s.upper_left = s.lower_left + nh * ey;
    return s;
}

EyeView off_axis_view(const Screen& screen, const Vec3& eye_m, double near_m, double far_m) {
    if (!is_finite(screen.lower_left) || !is_finite(screen.lower_right) || !is_finite(screen.upper_left) ||
        !is_finite(eye_m) || !std::isfinite(near_m) || !std::isfinite(far_m))
        throw Error("off_axis_view: screen corners, eye position and near/far must be finite");
    if (!(near_m > 0.0) || !(far_m > near_m))
        throw Error("off_axis_view: need 0 < near_m < far_m (got near_m = " + std::to_string(near_m) +
                    ", far_m = " + std::to_string(far_m) + ")");
    const Vec3 right = screen.lower_right - screen.lower_left;
    const Vec3 up = screen.upper_left - screen.lower_left;
    const double wr = glm::length(right), hu = glm::length(up);
    if (!(wr > 0.0) || !(hu > 0.0))
        throw Error("off_axis_view: Screen corners are degenerate (zero width or height)");
    // Screen basis (Kooima section 2): vr, vu, vn.
    const Vec3 vr = right / wr;
    const Vec3 vu = up / hu;
    if (std::abs(glm::dot(vr, vu)) > 1e-6)
        throw Error("off_axis_view: Screen corners do not form a right angle at lower_left");
    const Vec3 vn = glm::normalize(glm::cross(vr, vu));

    // Eye-to-corner vectors and the eye-to-screen-plane distance d.
    const Vec3 va = screen.lower_left - eye_m;
    const Vec3 vb = screen.lower_right - eye_m;
    const Vec3 vc = screen.upper_left - eye_m;
    const double d = -glm::dot(va, vn);
    if (!(d > 0.0))
        throw Error("off_axis_view: the eye is on or behind the screen plane (distance " + std::to_string(d) +
                    " m along the screen normal)");

    // Frustum extents at the near plane.
    const double s = near_m / d;
    const double l = glm::dot(vr, va) * s;
    const double r = glm::dot(vr, vb) * s;
    const double b = glm::dot(vu, va) * s;
    const double t = glm::dot(vu, vc) * s;
    const double n = near_m, f = far_m;

    // Perspective frustum for a right-handed eye space looking down -z, Vulkan clip space:
    // x_c = (2n x + (r+l) z)/(r-l), y_c = -(2n y + (t+b) z)/(t-b) (y down), z_c = (f z + n f)/(n - f), w_c = -z.
    Mat4 P(0.0);  // column-major: P[column][row]
    P[0][0] = 2.0 * n / (r - l);
    P[2][0] = (r + l) / (r - l);
    P[1][1] = -2.0 * n / (t - b);
    P[2][1] = -(t + b) / (t - b);
    P[2][2] = f / (n - f);
    P[3][2] = n * f / (n - f);
    P[2][3] = -1.0;

    // M^T: rows vr, vu, vn (world -> screen-aligned axes), then translate the eye to the origin.
    Mat4 view(1.0);
    for (int c = 0; c < 3; ++c) {
        view[c][0] = vr[c];
        view[c][1] = vu[c];
        view[c][2] = vn[c];
    }
    view[3][0] = -glm::dot(vr, eye_m);
    view[3][1] = -glm::dot(vu, eye_m);
    view[3][2] = -glm::dot(vn, eye_m);
    return EyeView{view, P, eye_m};
}

std::array<Vec3, 2> eye_positions(const Pose& head, double eye_separation_m) {
    if (!std::isfinite(eye_separation_m) || eye_separation_m < 0.0)
        throw Error("eye_positions: eye_separation_m must be finite and >= 0 (got " +
                    std::to_string(eye_separation_m) + ")");
    const double h = 0.5 * eye_separation_m;
    return {head.apply(Vec3(-h, 0.0, 0.0)), head.apply(Vec3(h, 0.0, 0.0))};
}

}  // namespace tridex::renderer
