// devices/scripted_path.hpp - a timed target trajectory for the simulated virtual hand.
#pragma once

#include <cstddef>
#include <vector>

#include "core/math.hpp"

namespace tridex::devices {

/// A smooth trajectory through timed waypoints (t_s in s, position in m, device frame).
/// Between waypoints i and i+1 it is the cubic Hermite curve whose tangents are the Catmull-Rom
/// ones for non-uniform times, m_i = (p_{i+1} - p_{i-1}) / (t_{i+1} - t_{i-1}), with m = 0 at the
/// first and last waypoint (the hand starts and ends at rest). Position is C1 (velocity continuous);
/// it passes exactly through every waypoint, and collinear waypoints equally spaced in time and
/// space give exactly constant velocity on every interior segment. Before the first waypoint the
/// path holds the first position, after the last it holds the last (velocity 0).
/// Evaluation is O(log n) (binary search), allocation-free and safe from the haptic thread.
class ScriptedPath {
public:
    /// Waypoints as parallel arrays: times t_s (s, strictly increasing, finite) and positions_m (m, finite).
    /// Throws tridex::Error naming the offending index when the arrays are empty or of different
    /// sizes, a time does not increase, or a value is not finite.
    ScriptedPath(std::vector<double> t_s, std::vector<Vec3> positions_m);

    /// A path that holds one position forever.
    static ScriptedPath hold(const Vec3& position_m);

    /// Target position at time t_s (s), m. Non-finite t_s gives the first waypoint.
    Vec3 position_at(double t_s) const;
    /// Target velocity at time t_s (s), m/s; zero outside [start_s(), end_s()].
    Vec3 velocity_at(double t_s) const;
    /// Time of the first waypoint, s.
    double start_s() const { return t_.front(); }
    /// Time of the last waypoint, s.
    double end_s() const { return t_.back(); }
    /// end_s() - start_s(), s (0 for a single waypoint).
    double duration() const { return t_.back() - t_.front(); }
    /// Number of waypoints (>= 1).
    std::size_t size() const { return t_.size(); }
    /// Waypoint times, s.
    const std::vector<double>& times() const { return t_; }
    /// Waypoint positions, m.
    const std::vector<Vec3>& positions() const { return p_; }

private:
    // Index i of the segment [t_i, t_{i+1}] holding t (requires t_0 <= t < t_last).
    std::size_t segment(double t) const;

    std::vector<double> t_;
    std::vector<Vec3> p_;
    std::vector<Vec3> m_;  // tangents at the waypoints, m/s
};

}  // namespace tridex::devices
