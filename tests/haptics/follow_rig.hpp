// tests/haptics/follow_rig.hpp - a god-object at 1 kHz on a snapshot that follows it as the sculpt thread's
// publisher does (ActiveSurface::window_centre_m, re-extracted when the centre moves 4 cells or the solid changes),
// cut from an analytic solid that a test may change under the resting tool; it keeps the figures the proxy tests
// report (distances to the HIP, force steps).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <utility>

#include "haptics/god_object.hpp"
#include "surfaces.hpp"

namespace tridex::test {

/// An analytic solid: its rays (surfaces.hpp) and its signed distance (world m; negative inside).
struct AnalyticSolid {
    RayFn rays;
    std::function<double(const Vec3&)> sdf;
};

/// The solid ball of radius r_m about centre_m (m) on a lattice of cell cell_m.
inline AnalyticSolid ball_solid(const Vec3& centre_m, double r_m, double cell_m) {
    return {ball_rays(centre_m, r_m, cell_m), [=](const Vec3& p) { return glm::length(p - centre_m) - r_m; }};
}

/// The half-space {x : n . x <= c_m} (n unit) on a lattice of cell cell_m with `nodes` nodes per axis.
inline AnalyticSolid half_space_solid(const Vec3& n, double c_m, double cell_m, int nodes) {
    return {half_space_rays(n, c_m, cell_m, nodes), [=](const Vec3& p) { return glm::dot(n, p) - c_m; }};
}

/// The figures of a run: worst proxy-to-HIP distances and force steps, N and m.
struct FollowFigures {
    int ticks = 0;
    double worst_gap_hip_outside_m = 0.0;  ///< largest |proxy - HIP| on ticks whose HIP centre is outside the solid
    int ticks_over_radius_hip_outside = 0; ///< such ticks with |proxy - HIP| > the tool's radius (+ 0.01 cell)
    double worst_gap_m = 0.0;              ///< largest |proxy - HIP| on any tick
    double worst_force_rise_n = 0.0;       ///< largest tick-to-tick rise of |F|
    double worst_force_step_n = 0.0;       ///< largest tick-to-tick |F_t - F_(t-1)|
    double worst_proxy_inside_m = 0.0;     ///< deepest the proxy's contact point went inside the solid (sdf < 0)
};

/// The rig. cell_m and nodes give the lattice (origin 0); params the contact; the solid may be replaced any time.
class FollowRig {
public:
    /// latency_ticks: the snapshot follows the proxy of that many ticks ago (the sculpt thread's publish delay).
    FollowRig(double cell_m, int nodes, const haptics::ContactParams& params, AnalyticSolid solid, int latency_ticks = 5)
        : cell_m_(cell_m), nodes_(nodes), radius_m_(params.tool_radius_m), god_(params), solid_(std::move(solid)),
          latency_(std::clamp(latency_ticks, 0, kMaxLatency)) {}

    /// Replaces the solid (material added, cut, undone): the next tick's snapshot shows it.
    void set_solid(AnalyticSolid solid) {
        solid_ = std::move(solid);
        stale_ = true;
    }

    /// One 1 kHz tick with the HIP at hip_m (m).
    haptics::ContactResult tick(const Vec3& hip_m) {
        // What the publisher saw `latency_` ticks ago (the proxy and HIP of that sample).
        const Vec3 seen_proxy = ticks_ > latency_ ? proxies_[(ticks_ - latency_) % kRing] : hip_m;
        const Vec3 seen_hip = ticks_ > latency_ ? hips_[(ticks_ - latency_) % kRing] : hip_m;
        const Vec3 where = ActiveSurface::window_centre_m(seen_proxy, seen_hip, radius_m_, kMarginM, cell_m_);
        if (!surface_ || stale_ || glm::length(where - centre_) > 4.0 * cell_m_) {
            centre_ = where;
            surface_ = published_surface(cell_m_, nodes_, centre_, radius_m_ + kMarginM, solid_.rays);
            surface_->sequence = ++sequence_;
            stale_ = false;
        }
        const haptics::ContactResult c = god_.update(*surface_, hip_m, 1e-3);
        ++ticks_;
        proxies_[ticks_ % kRing] = c.proxy_m;
        hips_[ticks_ % kRing] = hip_m;
        record(hip_m, c);
        return c;
    }

    /// Starts the figures again (the tick count too).
    void reset_figures() {
        f_ = FollowFigures{};
        have_force_ = false;
    }
    /// The figures so far.
    const FollowFigures& figures() const { return f_; }
    /// The solid now.
    const AnalyticSolid& solid() const { return solid_; }

private:
    static constexpr double kMarginM = 0.003;  // the publisher's motion margin, m
    static constexpr int kMaxLatency = 30;
    static constexpr int kRing = 32;

    void record(const Vec3& hip, const haptics::ContactResult& c) {
        ++f_.ticks;
        const double gap = glm::length(c.proxy_m - hip);
        f_.worst_gap_m = std::max(f_.worst_gap_m, gap);
        // Outside by more than a hundredth of a cell (a HIP exactly on the surface is a ball half in).
        if (solid_.sdf(hip) > 0.01 * cell_m_) {
            f_.worst_gap_hip_outside_m = std::max(f_.worst_gap_hip_outside_m, gap);
            if (gap > radius_m_ + 0.01 * cell_m_) ++f_.ticks_over_radius_hip_outside;
        }
        if (c.contact) f_.worst_proxy_inside_m = std::max(f_.worst_proxy_inside_m, -solid_.sdf(c.contact_point_m));
        if (have_force_) {
            f_.worst_force_rise_n = std::max(f_.worst_force_rise_n, glm::length(c.force_n) - glm::length(force_));
            f_.worst_force_step_n = std::max(f_.worst_force_step_n, glm::length(c.force_n - force_));
        }
        force_ = c.force_n;
        have_force_ = true;
    }

    double cell_m_;
    int nodes_;
    double radius_m_;
    haptics::GodObject god_;
    AnalyticSolid solid_;
    std::unique_ptr<ActiveSurface> surface_;
    Vec3 centre_{0.0};
    int latency_;
    long ticks_ = 0;
    std::array<Vec3, kRing> proxies_{};
    std::array<Vec3, kRing> hips_{};
    bool stale_ = true;
    std::uint64_t sequence_ = 0;
    Vec3 force_{0.0};
    bool have_force_ = false;
    FollowFigures f_;
};

}  // namespace tridex::test
