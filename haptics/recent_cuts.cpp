// haptics/recent_cuts.cpp - the subtracting tool's own recent sweeps, taken as cut before the snapshot shows them.
#include "haptics/recent_cuts.hpp"

#include <algorithm>
#include <cmath>

#include "core/capsule_chord.hpp"

namespace tridex::haptics {

namespace {

constexpr double kMinLengthCells = 1e-6;  // an interval shorter than this after a cut vanishes

}  // namespace

bool ray_capsule_chord(int axis, double u, double v, const Vec3& a, const Vec3& b, double r, double& t0, double& t1) {
    if (axis < 0 || axis > 2) return false;
    Vec3 p(0.0), d(0.0);
    p[(axis + 1) % 3] = u;
    p[(axis + 2) % 3] = v;
    d[axis] = 1.0;
    return chord::capsule_chord<double>(p, d, a, b, r, t0, t1);
}

bool cut_ray(ActiveSurface::Window& w, int iu, int iv, double c0, double c1) {
    if (!(c0 <= c1) || iu < 0 || iv < 0 || iu >= ActiveSurface::kWindow || iv >= ActiveSurface::kWindow) return false;
    constexpr int kK = ActiveSurface::kMaxIntervals;
    const int ray = iu + ActiveSurface::kWindow * iv;
    const int n = w.count[ray];
    // Pieces left: each interval loses [c0, c1]; at most one (the one holding the chord) splits in two.
    std::array<double, 2 * (kK + 1)> dep{};
    std::array<std::uint8_t, kK + 1> mat{};
    int m = 0;
    bool changed = false;
    const auto keep = [&](double e, double x, std::uint8_t id) {
        if (!(x - e >= kMinLengthCells) || m > kK) return;
        dep[2 * m] = e;
        dep[2 * m + 1] = x;
        mat[m] = id;
        ++m;
    };
    for (int k = 0; k < n && k < kK; ++k) {
        const double e = w.depth[(ray * kK + k) * 2], x = w.depth[(ray * kK + k) * 2 + 1];
        const std::uint8_t id = w.material[ray * kK + k];
        if (c1 <= e || c0 >= x) {  // untouched
            keep(e, x, id);
            continue;
        }
        changed = true;
        keep(e, c0, id);
        keep(c1, x, id);
    }
    if (!changed) return false;
    int first = 0;
    if (m > kK) {  // keep the kK pieces nearest the chord's middle (the window keeps those nearest the tool)
        const double mid = 0.5 * (c0 + c1);
        const auto far = [&](int i) { return std::min(std::abs(dep[2 * i] - mid), std::abs(dep[2 * i + 1] - mid)); };
        first = far(0) > far(m - 1) ? 1 : 0;  // pieces are in order: drop the farther end
        w.truncated = true;
    }
    const int kept = std::min(m, kK);
    for (int k = 0; k < kept; ++k) {
        w.depth[(ray * kK + k) * 2] = static_cast<float>(dep[2 * (first + k)]);
        w.depth[(ray * kK + k) * 2 + 1] = static_cast<float>(dep[2 * (first + k) + 1]);
        w.material[ray * kK + k] = mat[first + k];
    }
    w.count[ray] = static_cast<std::uint8_t>(kept);
    return true;
}

void RecentCuts::clear() {
    head_ = 0;
    count_ = 0;
    added_ = 0;
    scratch_upto_ = 0;
    have_last_pushed_ = false;
}

bool RecentCuts::note(const ToolSample& s, bool pushed) {
    if (!pushed) return false;
    const bool had = have_last_pushed_;
    const Vec3 from = last_pushed_m_;
    last_pushed_m_ = s.position;
    have_last_pushed_ = true;
    if (!had || s.op != ToolOp::kSubtract || s.tool.kind != ToolKind::kBall) return false;
    return add(from, s.position, s.tool.radius_m, s.made_s);
}

bool RecentCuts::add(const Vec3& from_m, const Vec3& to_m, double radius_m, double made_s) {
    if (!is_finite(from_m) || !is_finite(to_m) || !(radius_m > 0.0) || !std::isfinite(radius_m) ||
        !std::isfinite(made_s))
        return false;
    ring_[head_] = Sweep{from_m, to_m, radius_m, made_s};
    head_ = (head_ + 1) % kCapacity;
    count_ = std::min(count_ + 1, kCapacity);
    ++added_;
    return true;
}

void RecentCuts::subtract(const Sweep& s, ActiveSurface& out) {
    if (!(out.cell_m > 0.0)) return;
    const Vec3 a = (s.from_m - out.origin_m) / out.cell_m, b = (s.to_m - out.origin_m) / out.cell_m;
    const double r = s.radius_m / out.cell_m;
    const Vec3 lo = glm::min(a, b) - Vec3(r), hi = glm::max(a, b) + Vec3(r);
    for (int axis = 0; axis < 3; ++axis) {
        ActiveSurface::Window& w = out.sets[axis];
        if (w.nu <= 0 || w.nv <= 0) continue;
        const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
        const double st = out.window_spacing_cells(axis);
        const int iu0 = std::max(0, static_cast<int>(std::ceil((lo[ua] - w.u0) / st)));
        const int iu1 = std::min(w.nu - 1, static_cast<int>(std::floor((hi[ua] - w.u0) / st)));
        const int iv0 = std::max(0, static_cast<int>(std::ceil((lo[va] - w.v0) / st)));
        const int iv1 = std::min(w.nv - 1, static_cast<int>(std::floor((hi[va] - w.v0) / st)));
        for (int iv = iv0; iv <= iv1; ++iv) {
            for (int iu = iu0; iu <= iu1; ++iu) {
                if (w.count[iu + ActiveSurface::kWindow * iv] == 0) continue;
                const std::array<int, 2> uv = out.lattice_ray(axis, iu, iv);
                double t0 = 0.0, t1 = 0.0;
                if (ray_capsule_chord(axis, uv[0], uv[1], a, b, r, t0, t1)) cut_ray(w, iu, iv, t0, t1);
            }
        }
    }
}

const ActiveSurface& RecentCuts::apply(const ActiveSurface& snapshot, ActiveSurface& scratch) {
    const double applied = snapshot.applied_made_s;
    if (count_ == 0 || std::isnan(applied) || snapshot.sequence == 0 || !(snapshot.cell_m > 0.0)) return snapshot;
    // Sweeps are kept in the order made: the pending ones (made after the snapshot's newest sample) are the newest.
    int pending = 0;
    while (pending < count_ && ring_[(head_ - 1 - pending + 2 * kCapacity) % kCapacity].made_s > applied) ++pending;
    if (pending == 0) return snapshot;
    const std::uint64_t first = added_ - static_cast<std::uint64_t>(pending) + 1;
    const bool same = scratch_upto_ != 0 && scratch_sequence_ == snapshot.sequence && scratch_applied_s_ == applied;
    if (!same) {
        scratch = snapshot;  // a new snapshot: start again from it
        scratch_sequence_ = snapshot.sequence;
        scratch_applied_s_ = applied;
        scratch_upto_ = first - 1;
    }
    for (std::uint64_t serial = std::max(scratch_upto_ + 1, first); serial <= added_; ++serial) {
        const int back = static_cast<int>(added_ - serial);  // 0 = the newest
        subtract(ring_[(head_ - 1 - back + 2 * kCapacity) % kCapacity], scratch);
    }
    scratch_upto_ = added_;
    return scratch;
}

}  // namespace tridex::haptics
