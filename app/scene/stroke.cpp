// app/scene/stroke.cpp - planning the demo stroke over the workpiece's top surface, in one pass or in several passes
// joined by Peng et al.'s workspace moves.
#include "app/scene/stroke.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "compute/model/probe.hpp"
#include "core/error.hpp"
#include "core/format.hpp"

namespace tridex::app {

namespace {

constexpr int kSamples = 17;  // surface heights along a pass
constexpr int kScan = 96;     // candidate positions across the workpiece
// Workspace moves: a click is a press held kPress_s then released for kGap_s; the hand moves at most this fast
// when repositioning (lifted), so the virtual hand tracks it closely.
constexpr double kPress_s = 0.15, kGap_s = 0.15, kSettle_s = 0.2;

// The world's surface along x on the side facing +press_axis, through the workpiece's middle.
struct Surface {
    const compute::TriDexel& model;
    int a;     // press axis
    Vec3 c;    // workpiece centre
    double height(double x) const {
        Vec3 top;
        return compute::probe_top(model, a, Vec3(x, c.y, c.z), top) ? top[a] : std::nan("");
    }
    Vec3 at(double x, double h) const {
        Vec3 q(x, c.y, c.z);
        q[a] = h;
        return q;
    }
    // kSamples x positions from x0 over `length` and their smoothed heights (rays off the material take the
    // nearest height found). Returns false when no ray under the stretch holds material.
    bool sample(double x0, double length, std::vector<double>& xs, std::vector<double>& hs) const {
        xs.assign(kSamples, 0.0);
        std::vector<double> ys(kSamples);
        int found = 0;
        for (int i = 0; i < kSamples; ++i) {
            xs[i] = x0 + length * i / (kSamples - 1);
            ys[i] = height(xs[i]);
            found += std::isnan(ys[i]) ? 0 : 1;
        }
        if (found == 0) return false;
        for (int i = 0; i < kSamples; ++i) {
            if (!std::isnan(ys[i])) continue;
            for (int d = 1; d < kSamples; ++d) {
                if (i - d >= 0 && !std::isnan(ys[i - d])) { ys[i] = ys[i - d]; break; }
                if (i + d < kSamples && !std::isnan(ys[i + d])) { ys[i] = ys[i + d]; break; }
            }
        }
        hs.assign(kSamples, 0.0);
        for (int i = 0; i < kSamples; ++i) {
            double s = 0.0;
            for (int d = -2; d <= 2; ++d) s += ys[std::clamp(i + d, 0, kSamples - 1)];
            hs[i] = s / 5.0;
        }
        return true;
    }
};

// x of the stretch of `length` whose surface varies least (the bunny's back rather than its ears), among
// stretches that stay on material; the workpiece's centre when none does.
double flattest_start(const Surface& s, const Aabb& box, double length) {
    const double x_lo = box.lo.x, x_hi = box.hi.x - length;
    double best = s.c.x - 0.5 * length, best_range = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= kScan && x_hi > x_lo; ++k) {
        const double x0 = x_lo + (x_hi - x_lo) * k / kScan;
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        bool on_material = true;
        for (int i = 0; i < kSamples && on_material; ++i) {
            const double y = s.height(x0 + length * i / (kSamples - 1));
            on_material = !std::isnan(y);
            lo = std::min(lo, y);
            hi = std::max(hi, y);
        }
        if (on_material && hi - lo < best_range) {
            best_range = hi - lo;
            best = x0;
        }
    }
    return best;
}

}  // namespace

double workspace_move_s(WorkspaceMove move) {
    // jump: two clicks, then the hand goes back a pass length; drag: press, push half a pass, release, go back
    // one and a half.
    return move == WorkspaceMove::kJump ? 2.0 * (kPress_s + kGap_s) + 0.6 + kSettle_s
                                        : kPress_s + 0.5 + kGap_s + 0.8 + kSettle_s;
}

std::vector<Vec3> StrokePlan::device_offsets_m(double workspace_scale) const {
    std::vector<Vec3> out;
    out.reserve(world_m.size());
    for (std::size_t i = 0; i < world_m.size(); ++i)
        out.push_back((world_m[i] - centre_m - (i < shift_m.size() ? shift_m[i] : Vec3(0.0))) / workspace_scale);
    return out;
}

// `plan` begun `start_s` later: the hand holds its first waypoint until then.
StrokePlan delayed(StrokePlan plan, double start_s) {
    if (!std::isfinite(start_s) || start_s < 0.0)
        throw Error("stroke.start_s: must be a finite number of seconds >= 0, got " + format_number(start_s));
    if (start_s == 0.0) return plan;
    for (double& t : plan.t_s) t += start_s;
    for (devices::ButtonStep& b : plan.buttons) b.t_s += start_s;
    plan.t_s.insert(plan.t_s.begin(), 0.0);
    plan.world_m.insert(plan.world_m.begin(), plan.world_m.front());
    plan.shift_m.insert(plan.shift_m.begin(), plan.shift_m.front());
    return plan;
}

void place_plan(StrokePlan& plan, const Pose& world_from_model) {
    if (world_from_model.is_identity()) return;
    for (Vec3& w : plan.world_m) w = world_from_model.apply(w);
    for (Vec3& d : plan.shift_m) d = world_from_model.rotate(d);
    plan.centre_m = world_from_model.apply(plan.centre_m);
}

StrokePlan plan_stroke(const compute::TriDexel& model, const StrokeParams& p) {
    const Aabb box = model.lattice.bounds();
    const int a = p.press_axis;
    if (a != 1 && a != 2) throw Error("stroke: press_axis must be 1 (y, from above) or 2 (z, from the viewer)");
    if (p.passes < 1 || p.passes > 16) throw Error("stroke.passes: must be between 1 and 16, got " + std::to_string(p.passes));
    if (!(p.workspace_scale > 0.0)) throw Error("stroke: the workspace scale must be > 0");
    const Surface surf{model, a, box.centre()};
    const int n = p.passes;
    const double below = p.tool_radius_m - p.depth_m;  // tool centre height relative to the surface

    // One pass is no longer than 0.8 of the workpiece; several must fit on it together.
    double length = p.length_m;
    double x_start;
    if (n == 1) {
        length = std::min(p.length_m, 0.8 * box.size().x);
        x_start = flattest_start(surf, box, length);
    } else {
        if (n * length > box.size().x)
            throw Error("stroke: " + std::to_string(n) + " passes of " + format_number(length) +
                        " m do not fit on the workpiece, " + format_number(box.size().x) + " m long along x");
        x_start = surf.c.x - 0.5 * n * length;
    }
    double moves_s = 0.0;
    std::vector<WorkspaceMove> moves(n - 1, WorkspaceMove::kJump);
    for (int k = 0; k + 1 < n && k < static_cast<int>(p.moves.size()); ++k) moves[k] = p.moves[k];
    for (const WorkspaceMove m : moves) moves_s += workspace_move_s(m);
    const double T = (p.duration_s - moves_s) / n;  // one pass
    if (!(T >= 0.5))
        throw Error("stroke.duration_s: " + format_number(p.duration_s) + " s leaves under 0.5 s per pass after " +
                    format_number(moves_s) + " s of workspace moves; make it longer");

    StrokePlan plan;
    Vec3 shift(0.0);  // how far the workspace has moved, world m
    auto add = [&](double t, const Vec3& q) {
        plan.t_s.push_back(t);
        plan.world_m.push_back(q);
        plan.shift_m.push_back(shift);
    };
    double t0 = 0.0;
    std::vector<double> xs, hs;
    for (int k = 0; k < n; ++k) {
        if (!surf.sample(x_start + k * length, length, xs, hs))
            throw Error("stroke: no material under the carving pass; the workpiece is empty or too small");
        // The device workspace is centred on the pass's middle: on the surface for one pass; for several at the
        // lifted height, where the hand presses the button, so the moves carry the workspace along x only.
        if (k == 0) plan.centre_m = surf.at(xs[kSamples / 2], hs[kSamples / 2] + (n > 1 ? p.clearance_m : 0.0));
        const Vec3 lifted_start = surf.at(xs.front(), hs.front() + p.clearance_m);
        if (k == 0) add(0.0, lifted_start);  // later passes start where the last move left the hand
        add(t0 + 0.20 * T, surf.at(xs.front(), hs.front() + p.tool_radius_m + 0.002));  // hover just off the surface
        add(t0 + 0.30 * T, surf.at(xs.front(), hs.front() + below));                    // press in
        for (int i = 1; i < kSamples; ++i)                                              // carve along the surface
            add(t0 + 0.30 * T + 0.55 * T * i / (kSamples - 1), surf.at(xs[i], hs[i] + below));
        const Vec3 lifted_end = surf.at(xs.back(), hs.back() + p.clearance_m);
        add(t0 + 0.95 * T, lifted_end);  // lift off
        add(t0 + T, lifted_end);         // hold
        t0 += T;
        if (k + 1 == n) break;

        // Move the workspace forward by one pass length (x), the tool lifted, the hand at +length/2 from the
        // workspace centre (world units). Peng's rule (jump and drag gains 1): a press centres the box on the tool,
        // the box follows the tool while the button is held, and the release moves the workspace onto the box;
        // the hand holds still over a release, so the tool moves forward with the workspace.
        const Vec3 dx(length, 0.0, 0.0);
        Vec3 hand = lifted_end;  // world, under the mapping in effect
        // At a release the workspace moves onto the box, which is centred on the tool: by the tool's offset from
        // the workspace centre; the hand holds still, so the tool moves with it.
        auto release = [&] {
            const Vec3 move = hand - (plan.centre_m + shift);
            shift += move;
            hand += move;
        };
        double t = t0;
        if (moves[k] == WorkspaceMove::kJump) {
            for (int c = 0; c < 2; ++c) {  // each click moves it by the tool's offset, length / 2
                plan.buttons.push_back({t, 1u});
                plan.buttons.push_back({t + kPress_s, 0u});
                release();
                t += kPress_s + kGap_s;
                add(t, hand);
            }
        } else {
            plan.buttons.push_back({t, 1u});  // press: the box centres on the tool, length / 2 ahead
            add(t + kPress_s, hand);
            hand += 0.5 * dx;  // push the box another half pass ahead
            add(t + kPress_s + 0.5, hand);
            t += kPress_s + 0.5;
            plan.buttons.push_back({t + 0.5 * kGap_s, 0u});
            release();
            t += kGap_s;
            add(t, hand);
        }
        // Back, lifted, to the next pass's start: length (jump) or 1.5 length (drag) back in the device.
        const double back_s = moves[k] == WorkspaceMove::kJump ? 0.6 : 0.8;
        std::vector<double> nx, nh;
        if (!surf.sample(x_start + (k + 1) * length, length, nx, nh))
            throw Error("stroke: no material under the carving pass; the workpiece is empty or too small");
        add(t + back_s, surf.at(nx.front(), nh.front() + p.clearance_m));
        add(t + back_s + kSettle_s, surf.at(nx.front(), nh.front() + p.clearance_m));
        t0 = t + back_s + kSettle_s;
    }
    return delayed(std::move(plan), p.start_s);
}

}  // namespace tridex::app
