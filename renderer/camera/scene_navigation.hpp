// renderer/camera/scene_navigation.hpp - moving, turning and scaling the scene in front of the screen (the Wand).
#pragma once

#include "core/math.hpp"
#include "core/pose.hpp"
#include "renderer/camera/off_axis.hpp"

namespace tridex::renderer {

/// Where the scene (the workpiece and everything attached to it, scene metres) sits in the world (tracker space,
/// m): world_from_scene = T(translation) * R(rotation) * S(scale), a similarity. The wand or the mouse moves,
/// turns and scales it, as the Wand does in Peng et al., "Haptic Interface Technique in Large-Scale Virtual
/// Environment" (navigation of the scene in front of the PowerWall). Rotations and scalings act about a pivot
/// given in world m, which stays where it is. Not thread-safe: one thread navigates and reads.
class SceneNavigation {
public:
    /// Starts at `start` (rotation + translation) and uniform `start_scale`; the scale is kept in
    /// [min_scale, max_scale]. Throws tridex::Error for a non-finite pose, a zero quaternion, or scales that are
    /// not finite, not > 0, min_scale > max_scale, or start_scale outside [min_scale, max_scale].
    explicit SceneNavigation(const Pose& start = Pose{}, double start_scale = 1.0, double min_scale = 1e-3,
                             double max_scale = 1e3);

    /// The 4x4 similarity scene m -> world m.
    Mat4 world_from_scene() const;
    /// Its inverse, world m -> scene m.
    Mat4 scene_from_world() const;
    /// A scene point (scene m) in the world (m).
    Vec3 to_world(const Vec3& p_scene) const;
    /// A world point (m) in the scene (scene m).
    Vec3 to_scene(const Vec3& p_world) const;
    /// The rigid part (rotation and translation) of world_from_scene.
    Pose pose() const { return Pose{translation_, rotation_}; }
    /// The uniform scale, world m per scene m.
    double scale() const { return scale_; }

    /// Moves the scene by d_world_m (m). Throws tridex::Error when d is not finite.
    void translate(const Vec3& d_world_m);
    /// Turns the scene by `rotation` (normalised) about pivot_world_m (m). Throws tridex::Error for a zero or
    /// non-finite quaternion or a non-finite pivot.
    void rotate(const Quat& rotation, const Vec3& pivot_world_m);
    /// Turns the scene by angle_rad about the world axis `axis` (normalised) through pivot_world_m.
    /// Throws tridex::Error for a zero or non-finite axis, a non-finite angle or pivot.
    void rotate(const Vec3& axis, double angle_rad, const Vec3& pivot_world_m);
    /// Scales the scene by `factor` about pivot_world_m (the pivot stays fixed); the result is clamped to
    /// [min_scale, max_scale]. Returns the factor actually applied. Throws tridex::Error when factor is not finite
    /// and > 0 or the pivot is not finite.
    double scale(double factor, const Vec3& pivot_world_m);
    /// Grab and drag with the wand: the scene follows the wand's rigid motion from `wand_before` to `wand_after`
    /// (world poses), as if held by it: world_from_scene <- (after * before^-1) * world_from_scene.
    /// Throws tridex::Error for non-finite poses or zero quaternions.
    void wand_drag(const Pose& wand_before, const Pose& wand_after);
    /// Back to the start pose and scale.
    void reset();

private:
    Pose start_;
    double start_scale_, min_scale_, max_scale_;
    Vec3 translation_{0.0};
    Quat rotation_{1.0, 0.0, 0.0, 0.0};
    double scale_ = 1.0;
};

/// How mouse deltas navigate the scene: drags along the screen's right/up axes and a pivot, world m.
struct MouseNavigation {
    Vec3 right_axis{1.0, 0.0, 0.0};   ///< world direction of +x on screen (unit)
    Vec3 up_axis{0.0, 1.0, 0.0};      ///< world direction of +y (up) on screen (unit)
    Vec3 pivot_m{0.0};                ///< the point turns and zooms keep fixed, world m
    double metres_per_pixel = 0.001;  ///< pan distance per pixel of drag, m
    double radians_per_pixel = 0.005; ///< orbit angle per pixel of drag, rad
    double scale_per_step = 1.1;      ///< zoom factor per wheel step (> 1)

    /// Axes from `screen` (right = lower_left->lower_right, up = lower_left->upper_left, normalised), pivot at
    /// the screen's centre, pan gain = screen width / width_px (a drag moves the scene with the cursor on the
    /// screen plane). Throws tridex::Error for a degenerate screen or width_px < 1.
    static MouseNavigation for_screen(const Screen& screen, int width_px);
};

/// Drag to pan: moves the scene by dx_px * right - dy_px * up (pixels; dy grows downwards) times metres_per_pixel.
/// Throws tridex::Error for non-finite deltas.
void mouse_pan(SceneNavigation& nav, const MouseNavigation& mouse, double dx_px, double dy_px);
/// Drag to orbit: turns the scene about the pivot, dx_px about the up axis (drag right turns the front of the
/// scene to the right) and dy_px about the right axis (drag down tips its top towards the viewer).
/// Throws tridex::Error for non-finite deltas.
void mouse_orbit(SceneNavigation& nav, const MouseNavigation& mouse, double dx_px, double dy_px);
/// Wheel to zoom: scales by scale_per_step^steps about the pivot (steps > 0 enlarge). Returns the applied factor.
/// Throws tridex::Error for non-finite steps or scale_per_step not > 0.
double mouse_zoom(SceneNavigation& nav, const MouseNavigation& mouse, double steps);

}  // namespace tridex::renderer
