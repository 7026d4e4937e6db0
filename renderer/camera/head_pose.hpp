// renderer/camera/head_pose.hpp - where the viewer's head is: fixed, scripted, tracked, or moved by keyboard and mouse.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "core/aabb.hpp"
#include "core/pose.hpp"
#include "core/triple_buffer.hpp"

namespace tridex::renderer {

/// A source of the head pose (tracker space, m; the head's +x axis points to the viewer's right, +y up and
/// +z backwards, so eye_positions() puts the eyes at -/+ half the eye separation along +x). Times are
/// session seconds on one clock shared by the caller and the provider. One caller (the render thread).
class HeadPoseProvider {
public:
    virtual ~HeadPoseProvider() = default;
    /// The head pose at session time t_s (s). Never throws for a finite t_s.
    virtual Pose head_at(double t_s) = 0;
};

/// A head that never moves.
class FixedHead final : public HeadPoseProvider {
public:
    /// Throws tridex::Error when the position is not finite or the orientation is not a unit quaternion
    /// (| |q| - 1 | > 1e-6).
    explicit FixedHead(const Pose& pose);
    /// The fixed pose, whatever t_s.
    Pose head_at(double t_s) override;

private:
    Pose pose_;
};

/// One timed head pose of a script.
struct HeadWaypoint {
    double t_s = 0.0;  ///< session time, s
    Pose pose;         ///< head pose at t_s
};

/// A head following timed waypoints: position interpolated linearly, orientation by slerp (Shoemake, "Animating
/// Rotation with Quaternion Curves", 1985) along the shorter arc (q and -q are the same rotation); before the
/// first waypoint the first pose, after the last the last pose, or, when `loop`, the script repeats with period
/// (last t - first t).
class ScriptedHead final : public HeadPoseProvider {
public:
    /// Throws tridex::Error when `waypoints` is empty, a time or position is not finite, times do not strictly
    /// increase, an orientation is not a unit quaternion (| |q| - 1 | > 1e-6), or `loop` is set with fewer than
    /// two waypoints. The message names the waypoint index.
    explicit ScriptedHead(std::vector<HeadWaypoint> waypoints, bool loop = false);
    /// The interpolated pose at t_s (s).
    Pose head_at(double t_s) override;

private:
    std::vector<HeadWaypoint> waypoints_;
    bool loop_;
};

/// What a TrackerHead returned last.
struct TrackerStatus {
    bool tracked = false;   ///< true: the newest sample was fresh; false: the fallback pose was used
    /// t_s - time of the newest sample, s (0 if the sample is newer; inf if none; NaN for a NaN t_s)
    double age_s = 0.0;
    std::uint64_t fallbacks = 0;  ///< how many times the provider switched from tracked to the fallback pose
    std::string note;       ///< one line saying which pose is used and why
};

/// The interface a tracker driver fills: the driver thread push()es each pose with its sample time; the render
/// thread's head_at(t) returns the newest pose while it is at most `timeout_s` old, and otherwise falls back to
/// `fallback` and says so in status(). Lock-free hand-off (core TripleBuffer): exactly one pushing thread and one
/// reading thread; push() never blocks or allocates.
class TrackerHead final : public HeadPoseProvider {
public:
    /// Throws tridex::Error when `fallback` is not a finite pose with a unit orientation or timeout_s is not
    /// finite and > 0.
    TrackerHead(const Pose& fallback, double timeout_s = 0.1);
    /// Driver side: the newest tracker pose, sampled at t_s (s). Non-finite samples are ignored (counted in
    /// rejected()); a non-unit orientation is normalised.
    void push(const Pose& pose, double t_s);
    /// Reader side: the newest pushed pose if it is at most timeout_s older than t_s, else the fallback pose.
    Pose head_at(double t_s) override;
    /// Reader side: what the last head_at() returned and why.
    const TrackerStatus& status() const { return status_; }
    /// Samples ignored by push() because they were not finite (any thread).
    std::uint64_t rejected() const { return rejected_.load(std::memory_order_relaxed); }

private:
    struct Sample {
        Pose pose;
        double t_s = 0.0;
        bool valid = false;
    };
    Pose fallback_;
    double timeout_s_;
    TripleBuffer<Sample> slot_;
    TrackerStatus status_;
    std::atomic<std::uint64_t> rejected_{0};
};

/// Keys that move a head (or anything else) without a tracker; the window layer maps its key codes to these.
enum class MoveKey { kLeft, kRight, kUp, kDown, kForward, kBack };

/// A head moved by keyboard and mouse when no tracker is present. Held keys move it at `speed_m_per_s` along the
/// head's yaw frame (forward = the head's -z flattened onto the horizontal plane, right = its +x, up = world +y);
/// mouse deltas turn it: yaw about world +y, pitch about the head's right axis, clamped to +/- 89 degrees.
/// The position is clamped to `limits_m` (e.g. the tracked volume in front of the screen; an empty box means no
/// limit). Input calls and head_at() come from one thread.
class KeyboardMouseHead final : public HeadPoseProvider {
public:
    /// `home`: the start pose (the yaw and pitch of its gaze direction -z are kept, any roll is dropped);
    /// speed_m_per_s > 0: key translation speed; radians_per_pixel > 0: mouse turn rate.
    /// Throws tridex::Error for a non-finite or non-positive speed or turn rate, a non-finite home position, or a
    /// home outside non-empty limits.
    KeyboardMouseHead(const Pose& home, double speed_m_per_s = 0.3, double radians_per_pixel = 0.002,
                      const Aabb& limits_m = Aabb{});
    /// A key went down (pressed = true) or up. Movement is integrated from the time of the previous head_at().
    void key(MoveKey key, bool pressed);
    /// The mouse moved by (dx_px right, dy_px down) pixels while turning the head; dx > 0 turns it right (yaw
    /// negative about +y), dy > 0 tilts it down. Non-finite deltas are ignored.
    void mouse_turn(double dx_px, double dy_px);
    /// Back to the home pose, keys released.
    void reset();
    /// Advances held-key motion by t_s - (previous t_s) (clamped to >= 0; 0 on the first call) and returns the pose.
    Pose head_at(double t_s) override;

private:
    Pose current() const;
    Pose home_;
    double speed_, rad_per_px_;
    Aabb limits_;
    Vec3 position_{0.0};
    double yaw_ = 0.0, pitch_ = 0.0, home_yaw_ = 0.0, home_pitch_ = 0.0;
    bool held_[6] = {false, false, false, false, false, false};
    double last_t_ = 0.0;
    bool started_ = false;
};

}  // namespace tridex::renderer
