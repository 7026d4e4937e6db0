// renderer/camera/off_axis.hpp - head-tracked stereo cameras for a fixed screen (off-axis frustum).
#pragma once

#include <array>

#include "core/math.hpp"
#include "core/pose.hpp"

namespace tridex::renderer {

/// A flat rectangular screen given by three corners in tracker/world space (m). The screen's right
/// axis is lower_right - lower_left, its up axis upper_left - lower_left, its normal right x up
/// (pointing towards the viewer).
struct Screen {
    Vec3 lower_left{0.0};
    Vec3 lower_right{0.0};
    Vec3 upper_left{0.0};

    /// The PowerWall: 10 ft x 7.5 ft (3.048 m x 2.286 m), centred at the origin in the z = 0 plane,
    /// x to the right, y up, normal +z (the viewer stands at z > 0).
    static Screen powerwall();
    /// A 24-inch class desktop monitor: 0.53 m x 0.30 m (about 16:9), centred at the origin in the z = 0 plane,
    /// x to the right, y up, normal +z; the viewer's head is expected about 0.6 m in front (z = 0.6).
    static Screen desktop_monitor();
    /// Width |lower_right - lower_left| and height |upper_left - lower_left|, m.
    double width() const;
    double height() const;
    /// This screen widened or heightened about its centre, in its own plane, to width / height = `aspect` (a window's
    /// pixel aspect): the result contains this screen, so what was framed stays in view and nothing is stretched when a
    /// desk window is resized. Returns *this for an aspect that is not finite and positive or a degenerate screen.
    Screen fitted_to_aspect(double aspect) const;
};

/// One eye's camera: world -> eye (view), eye -> Vulkan clip space (projection), and the eye position.
struct EyeView {
    Mat4 view;        ///< world (m) -> eye space: origin at the eye, axes = screen right/up/normal
    Mat4 projection;  ///< eye space -> clip space; x_ndc right, y_ndc down, depth 0 (near) .. 1 (far)
    Vec3 eye_m{0.0};  ///< eye position, world m
};

/// View and projection for an eye at eye_m looking through `screen` (Kooima, "Generalized Perspective
/// Projection", 2009: screen basis vr, vu, vn; frustum extents l, r, b, t at the near plane from the
/// eye-to-corner vectors; P * M^T * T(-eye)). Vulkan conventions: depth maps near -> 0, far -> 1, and y
/// is flipped so that the screen's upper edge lands on framebuffer row 0 (the image is upright); the
/// screen corners map to NDC lower_left (-1, +1), lower_right (+1, +1), upper_left (-1, -1).
/// Throws tridex::Error if the eye is on or behind the screen plane, the screen corners are degenerate
/// or not at a right angle (|cos| > 1e-6), near_m <= 0, far_m <= near_m, or any input is not finite.
EyeView off_axis_view(const Screen& screen, const Vec3& eye_m, double near_m, double far_m);

/// Left and right eye positions (world m): head position -/+ eye_separation_m / 2 along the head's
/// right (+x) axis, i.e. head.apply((-s/2, 0, 0)) and head.apply((+s/2, 0, 0)).
/// Throws tridex::Error if eye_separation_m is negative or not finite.
std::array<Vec3, 2> eye_positions(const Pose& head, double eye_separation_m);

}  // namespace tridex::renderer
