// devices/scripted_orientation.hpp - a timed orientation target for the simulated virtual hand.
#pragma once

#include <cstddef>
#include <vector>

#include "core/math.hpp"

namespace tridex::devices {

/// A rotation trajectory through timed unit quaternions (stylus frame -> device frame).
/// Between waypoints i and i+1 it is the slerp (constant angular velocity along the shortest arc):
///   q(t) = exp(s * w_i) * q_i,  s = (t - t_i) / (t_{i+1} - t_i),  w_i = rotvec(q_{i+1} * q_i^-1),
/// so the angular velocity is w_i / (t_{i+1} - t_i) (rad/s, device frame), constant on each segment
/// and zero outside [start_s(), end_s()]. Before the first waypoint it holds the first orientation,
/// after the last the last. q and -q are the same rotation: each waypoint is taken on the same side
/// as the previous one, so no segment turns the long way round.
/// Evaluation is O(log n) (binary search), allocation-free and safe from the haptic thread.
class ScriptedOrientation {
public:
    /// Waypoints as parallel arrays: times t_s (s, finite, strictly increasing) and orientations (unit
    /// quaternions, |q| within 1e-6 of 1; they are renormalised). Throws tridex::Error naming the
    /// offending index when the arrays are empty or of different sizes, a time does not increase, or a
    /// value is not finite or not unit.
    ScriptedOrientation(std::vector<double> t_s, std::vector<Quat> orientations);

    /// An orientation held forever.
    static ScriptedOrientation hold(const Quat& orientation);

    /// Target orientation at time t_s (s), a unit quaternion. Non-finite t_s gives the first waypoint.
    Quat orientation_at(double t_s) const;
    /// Target angular velocity at time t_s (s), rad/s in the device frame; zero outside the time range.
    Vec3 angular_velocity_at(double t_s) const;
    /// Time of the first waypoint, s.
    double start_s() const { return t_.front(); }
    /// Time of the last waypoint, s.
    double end_s() const { return t_.back(); }
    /// Number of waypoints (>= 1).
    std::size_t size() const { return t_.size(); }
    /// Waypoint times, s.
    const std::vector<double>& times() const { return t_; }
    /// Waypoint orientations (unit, each on the same side as the previous one).
    const std::vector<Quat>& orientations() const { return q_; }

private:
    // Index i of the segment [t_i, t_{i+1}] holding t (requires t_0 < t < t_last).
    std::size_t segment(double t) const;

    std::vector<double> t_;
    std::vector<Quat> q_;
    std::vector<Vec3> w_;  // rotation vector of segment i, device frame, rad
};

}  // namespace tridex::devices
