// app/input/mouse_stylus.hpp - the desk mouse as a virtual stylus: cursor, buttons and wheel to a tool target on the
// workpiece surface under the cursor.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "app/input/surface_pick.hpp"
#include "core/tool_sample.hpp"
#include "renderer/camera/off_axis.hpp"

namespace tridex::app {

/// What the stylus asks of the tool this frame (world m).
struct StylusTarget {
    Vec3 hip_m{0.0};             ///< where the tool centre (HIP) should be, world m
    std::uint32_t buttons = 0;   ///< devices::mouse_buttons bits (kEngage: left held, kStylus: right held)
    bool on_surface = false;     ///< the cursor ray met the surface (false: the tool hovers at the last depth)
    /// The hand's turn (world, unit): identity but while placing (ToolOp::kPlace), whose wheel turns the held
    /// workpiece about the vertical.
    Quat orientation{1.0, 0.0, 0.0, 0.0};
};

/// The mouse stylus (one thread, the window's). The tool rides on the surface under the cursor: a ray from the
/// eye through the cursor pixel (cursor_ray) meets the contoured surface (pick_surface) at P with normal n, and
/// the tool centre goes to P + (r - d) n, with r the tool radius and d = 0 while the left button is up (the
/// tool rests on the surface) and d = depth_m() while it is held (pressed in: a drag carves a groove of that
/// depth along the cursor's path; a negative depth holds the tool off the surface, so that turning the wheel
/// toward the user while the button is held draws the tool out, and pull draws the surface out after it). While
/// the left button is held the ray runs against the surface as it was when the button went down, so the groove
/// follows the original surface instead of drilling into its own cut, and a pulled surface does not carry the
/// tool with it. A ray that misses keeps the tool at the last hit's distance along the new ray (hovering). The
/// right button is the stylus button (workspace techniques). The wheel sets the depth in whole steps of
/// depth_step_m (a tenth of the radius), from -kMaxDepthSteps to kMaxDepthSteps. Choosing another operation resets
/// the depth to that operation's default (default_depth_steps), as a sculpting program restores a brush's own
/// strength: a depth set for a deep cut does not carry into paint or clay.
/// For a flat end (its axis up, +y: the mouse turns no tool) r above is its support distance along -n, so its
/// rim, end face or shank rests on the surface; for a mesh tool, its bounding radius.
/// Placing (ToolOp::kPlace): the tool rests on the surface (depth 0); while the left button is held the workpiece
/// follows the tool, so the tool is dragged at the distance from the eye it had when the button went down (across the
/// view, not over the moving surface) and each wheel step turns the hand, and so the held workpiece, by kTurnStepDeg
/// about the world's vertical (+y) through the tool; the turn ends with the drag.
/// resize() scales the tool (ball or flat end; a mesh tool keeps its size) in steps of kSizeStep, from
/// kSizeStep^-kMaxSizeSteps to kSizeStep^kMaxSizeSteps times the scene's tool; the depth scales with it.
class MouseStylus {
public:
    static constexpr double kSizeStep = 1.25;  ///< tool size factor per resize step
    static constexpr int kMaxSizeSteps = 6;    ///< resize steps allowed each way from the scene's tool
    static constexpr int kMaxDepthSteps = 20;  ///< wheel steps allowed each way from the surface (two radii)
    static constexpr double kTurnStepDeg = 15.0;  ///< placing: the held workpiece's turn per wheel step, degrees

    /// tool_radius_m: the ball's radius, m (> 0; the default depth, ten wheel steps); aim_m: where the tool hovers before
    /// the first hit (world m, e.g. in front of the workpiece). Throws tridex::Error for a radius that is not
    /// finite and positive, or a non-finite aim point.
    MouseStylus(double tool_radius_m, const Vec3& aim_m);
    /// The same for the session's tool `tool` (core/tool_shape.hpp; radius_m > 0, the default depth). Throws
    /// tridex::Error as validate_tool does, or for a non-finite aim point.
    MouseStylus(const ToolShape& tool, const Vec3& aim_m);

    /// The cursor position, pixels from the window's top-left; non-finite values are ignored.
    void set_cursor(double x_px, double y_px);
    /// The left button (engage) down or up.
    void set_left(bool down) { left_ = down; }
    /// The right button (stylus button) down or up.
    void set_right(bool down) { right_ = down; }
    /// Wheel steps (+ = away from the user = deeper, - = out of the surface), summed and taken in whole steps (a
    /// touchpad's fractions add up); the depth stays in [-2 r, 2 r]. Non-finite steps are ignored.
    void wheel(double steps);
    /// What the tool applies while engaged (subtract, union, paint, push, smooth, pull, grab, or place: the workpiece
    /// follows; kNone is ignored). A
    /// different operation than the current one resets the depth to default_depth_steps(op).
    void set_op(ToolOp op);
    /// The depth an operation starts with, in wheel steps (tenths of the radius): subtract and union a full radius
    /// (a groove or ridge as wide as the tool), paint three tenths (the colour follows the surface without cutting),
    /// push, smooth, pull and grab half a radius, place none (the tool rests on the surface it holds).
    static int default_depth_steps(ToolOp op);
    /// Scales the tool by kSizeStep^steps (within the limits above). Returns false, changing nothing, for a
    /// mesh tool or at the limit.
    bool resize(int steps);
    /// The tool in use (the scene's tool, scaled by resize()).
    const ToolShape& tool() const { return tool_; }
    /// resize() steps from the scene's tool, in [-kMaxSizeSteps, kMaxSizeSteps].
    int size_steps() const { return size_steps_; }

    ToolOp op() const { return op_; }                 ///< the chosen Boolean
    double depth_m() const { return depth_steps_ * depth_step_m_; }  ///< how deep the held tool presses in, m (< 0: off)
    double radius_m() const { return radius_m_; }     ///< the tool radius, m
    bool left() const { return left_; }               ///< left button held
    bool right() const { return right_; }             ///< right button held
    bool has_cursor() const { return have_cursor_; }  ///< a cursor position was given
    double cursor_x() const { return x_px_; }          ///< the cursor, pixels from the window's left
    double cursor_y() const { return y_px_; }          ///< the cursor, pixels from the window's top
    double depth_step_m() const { return depth_step_m_; }  ///< depth change per wheel step, m

    /// This frame's target: the cursor's ray (cursor_ray from `eye_m` through `screen`, image width_px x
    /// height_px) against `live` (the newest published surface; while the left button is held, the surface as
    /// it was when it went down). Before any cursor position, the tool hovers at the aim point. Never throws;
    /// the target is always finite.
    StylusTarget update(const renderer::Screen& screen, const Vec3& eye_m, double width_px, double height_px,
                        const PickSurface& live);

    /// One overlay line: "mouse stylus: subtract (1/2/3), ball r 6 mm ([ ]), depth 6 mm (wheel)[, engaged]".
    std::string status() const;

private:
    ToolShape base_;  // the scene's tool
    ToolShape tool_;  // the tool in use
    int size_steps_ = 0;
    double radius_m_;
    int depth_steps_ = default_depth_steps(ToolOp::kSubtract);  // the depth in wheel steps (tenths of the radius)
    double wheel_rest_ = 0.0;  // wheel steps not yet taken (fractions)
    double depth_step_m_;
    Vec3 aim_m_;
    double x_px_ = 0.0, y_px_ = 0.0;
    bool have_cursor_ = false, left_ = false, right_ = false;
    ToolOp op_ = ToolOp::kSubtract;
    // The HIP's height above a surface of unit normal `normal` at which the resting tool touches it, m.
    double rest_height_m(const Vec3& normal) const;
    std::optional<PickSurface> pressed_;  // the surface when the left button went down
    double last_distance_m_ = -1.0;       // the last hit's distance along its ray, m (< 0: none yet)
    double grip_distance_m_ = -1.0;       // placing: the held tool's distance from the eye, m (< 0: not held)
    int turn_steps_ = 0;                  // placing: wheel steps turned while held
    Vec3 last_hip_m_{0.0};
};

}  // namespace tridex::app
