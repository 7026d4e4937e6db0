// app/stroke.cpp - planning the demo stroke over the workpiece's top surface.
#include "app/stroke.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "compute/model/probe.hpp"
#include "core/error.hpp"

namespace tridex::app {

StrokePlan plan_stroke(const compute::TriDexel& model, const StrokeParams& p) {
    const Aabb box = model.lattice.bounds();
    const Vec3 c = box.centre();
    const double half = 0.5 * std::min(p.length_m, 0.8 * box.size().x);
    constexpr int kSamples = 17;  // surface heights along the pass
    constexpr int kScan = 96;     // candidate positions across the workpiece

    // Surface height along world x on the side facing +press_axis, through the workpiece's middle
    // (the rays of the press axis' own set); at(x, h) is the world point at height h over x.
    const int a = p.press_axis;
    if (a != 1 && a != 2) throw Error("stroke: press_axis must be 1 (y, from above) or 2 (z, from the viewer)");
    auto height_at = [&](double x) {
        Vec3 top;
        return compute::probe_top(model, a, Vec3(x, c.y, c.z), top) ? top[a] : std::nan("");
    };
    auto at = [&](double x, double h) {
        Vec3 q(x, c.y, c.z);
        q[a] = h;
        return q;
    };
    // Choose where the pass goes: the stretch of length 2*half whose top surface varies least
    // (on the bunny, its back rather than its ears), among stretches that stay on material.
    const double x_lo = box.lo.x + half, x_hi = box.hi.x - half;
    double best_x = c.x, best_range = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= kScan && x_hi > x_lo; ++k) {
        const double xc = x_lo + (x_hi - x_lo) * k / kScan;
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        bool on_material = true;
        for (int i = 0; i < kSamples && on_material; ++i) {
            const double y = height_at(xc - half + 2.0 * half * i / (kSamples - 1));
            on_material = !std::isnan(y);
            lo = std::min(lo, y);
            hi = std::max(hi, y);
        }
        if (on_material && hi - lo < best_range) {
            best_range = hi - lo;
            best_x = xc;
        }
    }

    std::vector<double> xs(kSamples), ys(kSamples);
    int found = 0;
    for (int i = 0; i < kSamples; ++i) {
        xs[i] = best_x - half + 2.0 * half * i / (kSamples - 1);
        ys[i] = height_at(xs[i]);
        found += std::isnan(ys[i]) ? 0 : 1;
    }
    if (found == 0) throw Error("stroke: no material under the carving pass; the workpiece is empty or too small");
    // Fill rays that missed the workpiece with the nearest found height.
    for (int i = 0; i < kSamples; ++i) {
        if (!std::isnan(ys[i])) continue;
        for (int d = 1; d < kSamples; ++d) {
            if (i - d >= 0 && !std::isnan(ys[i - d])) { ys[i] = ys[i - d]; break; }
            if (i + d < kSamples && !std::isnan(ys[i + d])) { ys[i] = ys[i + d]; break; }
        }
    }
    std::vector<double> smooth(kSamples);
    for (int i = 0; i < kSamples; ++i) {
        double s = 0.0, w = 0.0;
        for (int d = -2; d <= 2; ++d) {
            const int j = std::clamp(i + d, 0, kSamples - 1);
            s += ys[j];
            w += 1.0;
        }
        smooth[i] = s / w;
    }

    StrokePlan plan;
    const double T = p.duration_s;
    const double below = p.tool_radius_m - p.depth_m;  // ball centre height relative to the surface
    auto add = [&](double t, const Vec3& q) {
        plan.t_s.push_back(t);
        plan.world_m.push_back(q);
    };
    add(0.0, at(xs.front(), smooth.front() + p.clearance_m));
    add(0.20 * T, at(xs.front(), smooth.front() + p.tool_radius_m + 0.002));  // hover just off the surface
    add(0.30 * T, at(xs.front(), smooth.front() + below));                    // press in
    for (int i = 1; i < kSamples; ++i)                                        // carve along the surface
        add(0.30 * T + 0.55 * T * i / (kSamples - 1), at(xs[i], smooth[i] + below));
    add(0.95 * T, at(xs.back(), smooth.back() + p.clearance_m));              // lift off
    add(T, at(xs.back(), smooth.back() + p.clearance_m));                     // hold
    plan.centre_m = at(best_x, smooth[kSamples / 2]);
    return plan;
}

}  // namespace tridex::app
