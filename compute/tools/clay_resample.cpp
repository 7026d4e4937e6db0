// compute/tools/clay_resample.cpp - re-sampling a clay field into the three ray sets, and the volume-keeping beta.
#include "compute/tools/clay_resample.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "compute/tools/clay_volume_model.hpp"

namespace tridex::compute {
namespace {

struct Crossing {
    float t;
    std::uint8_t material;
};

/// Material of the ray's old end nearest to depth t (0 when the ray had none).
std::uint8_t nearest_material(const std::vector<Interval>& ray, float t) {
    std::uint8_t m = 0;
    float best = 3.4e38f;
    for (const Interval& iv : ray) {
        const float d0 = std::fabs(iv.enter - t), d1 = std::fabs(iv.exit - t);
        if (d0 < best) best = d0, m = iv.enter_material;
        if (d1 < best) best = d1, m = iv.exit_material;
    }
    return m;
}

}  // namespace

void clay_resample_ray(const std::vector<Interval>& ray, const ClayField& f, int axis, int u, int v, int lo, int hi,
                       float beta, std::vector<Interval>& out) {
    const ClayBox& b = f.box;
    int n[3];
    n[(axis + 1) % 3] = u;
    n[(axis + 2) % 3] = v;
    n[axis] = lo;
    const std::size_t base = b.index(n[0], n[1], n[2]);
    const std::size_t stride = b.stride(axis);
    thread_local std::vector<Crossing> xs;
    xs.clear();
    std::size_t q = 0;  // next old crossing (2 per interval)
    auto old_t = [&](std::size_t k) { return (k & 1u) ? ray[k >> 1].exit : ray[k >> 1].enter; };
    auto old_m = [&](std::size_t k) { return (k & 1u) ? ray[k >> 1].exit_material : ray[k >> 1].enter_material; };
    const std::size_t nx = 2 * ray.size();
    const float flo = static_cast<float>(lo);
    while (q < nx && old_t(q) < flo) xs.push_back({old_t(q), old_m(q)}), ++q;
    bool status = (q & 1u) != 0;  // the ray's status just below node lo
    for (int d = lo; d < hi; ++d) {
        const std::size_t i0 = base + static_cast<std::size_t>(d - lo) * stride, i1 = i0 + stride;
        const float s0 = f.s0[i0] + beta * f.s1[i0];
        const float s1 = f.s0[i1] + beta * f.s1[i1];
        const float fd1 = static_cast<float>(d + 1);
        if (s0 == 0.0f && s1 == 0.0f) {  // the edge keeps its old crossings
            while (q < nx && old_t(q) < fd1) xs.push_back({old_t(q), old_m(q)}), ++q;
            status = (q & 1u) != 0;
            continue;
        }
        const float p0 = f.phi[i0] + s0, p1 = f.phi[i1] + s1;
        // Status at each end: the field's where the node moved, the ray's own where it did not.
        const bool st0 = s0 != 0.0f ? p0 < 0.0f : status;
        std::size_t q1 = q;
        while (q1 < nx && old_t(q1) < fd1) ++q1;
        const bool st1 = s1 != 0.0f ? p1 < 0.0f : (q1 & 1u) != 0;
        q = q1;
        if (st0 != st1) {
            float t;
            if ((p0 < 0.0f) != (p1 < 0.0f)) {
                const float w = p0 / (p0 - p1);
                t = static_cast<float>(d) + std::clamp(w, 0.0f, 1.0f);
            } else {
                t = static_cast<float>(d) + 0.5f;  // the old ray disagreed with the field at its unmoved end
            }
            xs.push_back({t, nearest_material(ray, t)});
        }
        status = st1;
    }
    while (q < nx) xs.push_back({old_t(q), old_m(q)}), ++q;
    // Pair the crossings into sorted, disjoint, non-touching intervals; zero-length ones vanish.
    out.clear();
    for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
        const Crossing a = xs[k], e = xs[k + 1];
        if (!(a.t < e.t)) continue;
        if (!out.empty() && !(out.back().exit < a.t)) {  // touches the previous one: merge
            out.back().exit = std::max(out.back().exit, e.t);
            out.back().exit_material = e.material;
            continue;
        }
        out.push_back({a.t, e.t, a.material, e.material});
    }
}

double clay_ray_length(const std::vector<Interval>& ray) {
    double s = 0.0;
    for (const Interval& iv : ray) s += static_cast<double>(iv.exit) - static_cast<double>(iv.enter);
    return s;
}

void clay_note_resampled(const std::vector<Interval>& old, const ClayMovedRay& m, std::size_t k, ClayResampled& out) {
    out.changed[k] = clay_same_ray(old, out.rays[k]) ? 0 : 1;
    out.dlen[k] = out.changed[k] ? clay_ray_length(out.rays[k]) - m.old_length : 0.0;
}

bool clay_same_ray(const std::vector<Interval>& a, const std::vector<Interval>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].enter != b[i].enter || a[i].exit != b[i].exit || a[i].enter_material != b[i].enter_material ||
            a[i].exit_material != b[i].exit_material)
            return false;
    return true;
}

void clay_moved_nodes(const ClayField& f, std::vector<ClayMovedNode>& out) {
    const ClayBox& b = f.box;
    out.clear();
    const bool built = f.chords[0].size() == static_cast<std::size_t>(b.n(1)) * b.n(2);  // else scan the whole box
    for (int k = b.lo[2]; k <= b.hi[2]; ++k)
        for (int j = b.lo[1]; j <= b.hi[1]; ++j) {
            int ilo = b.lo[0], ihi = b.hi[0];
            if (built) ilo = f.chord(0, j, k)[0], ihi = f.chord(0, j, k)[1];
            for (int i = ilo; i <= ihi; ++i) {
                const std::size_t x = b.index(i, j, k);
                if (f.s0[x] != 0.0f || f.s1[x] != 0.0f) out.push_back({static_cast<std::uint32_t>(x), {i, j, k}});
            }
        }
}

void clay_moved_rays(const TriDexel& model, const ClayField& f, std::span<const ClayMovedNode> nodes,
                     std::vector<ClayMovedRay>& out) {
    const ClayBox& b = f.box;
    struct Span {
        int lo, hi;
        bool varies;
    };
    thread_local std::array<std::vector<Span>, 3> span;
    for (int a = 0; a < 3; ++a)
        span[a].assign(static_cast<std::size_t>(b.n((a + 1) % 3)) * b.n((a + 2) % 3), Span{1, 0, false});
    for (const ClayMovedNode& m : nodes)
        for (int a = 0; a < 3; ++a) {
            const int ua = (a + 1) % 3, va = (a + 2) % 3;
            Span& sp = span[a][static_cast<std::size_t>(m.n[ua] - b.lo[ua]) +
                               static_cast<std::size_t>(b.n(ua)) * (m.n[va] - b.lo[va])];
            if (sp.lo > sp.hi) sp.lo = sp.hi = m.n[a];
            sp.lo = std::min(sp.lo, m.n[a]);
            sp.hi = std::max(sp.hi, m.n[a]);
            sp.varies |= f.s1[m.x] != 0.0f;
        }
    out.clear();
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = model.sets[a];
        const int ua = (a + 1) % 3, va = (a + 2) % 3;
        for (int v = b.lo[va]; v <= b.hi[va]; ++v)
            for (int u = b.lo[ua]; u <= b.hi[ua]; ++u) {
                const Span& sp = span[a][static_cast<std::size_t>(u - b.lo[ua]) +
                                         static_cast<std::size_t>(b.n(ua)) * (v - b.lo[va])];
                if (sp.lo > sp.hi) continue;
                // Edges [d, d + 1] with a moved end: d in [lo - 1, hi], within the box.
                out.push_back({static_cast<std::uint8_t>(a), static_cast<std::uint32_t>(u + set.nu * v), u, v,
                               std::max(sp.lo - 1, b.lo[a]), std::min(sp.hi + 1, b.hi[a]), sp.varies,
                               clay_ray_length(set.ray(u, v))});
            }
    }
}

void clay_resample_on_cpu(const TriDexel& model, const ClayField& f, std::span<const ClayMovedRay> moved, float beta,
                          ClayResampled* fixed, ClayResampled& var) {
    for (std::size_t k = 0; k < moved.size(); ++k) {
        const ClayMovedRay& m = moved[k];
        ClayResampled* out = m.varies ? &var : fixed;
        if (!out) continue;
        const std::vector<Interval>& ray = model.sets[m.set].rays[m.index];
        clay_resample_ray(ray, f, m.set, m.u, m.v, m.lo, m.hi, m.varies ? beta : 0.0f, out->rays[k]);
        clay_note_resampled(ray, m, k, *out);
    }
}

namespace {

/// Sizes the slots of `r` for `n` moved rays (keeping the rays' storage).
void prepare(ClayResampled& r, std::size_t n) {
    if (r.rays.size() < n) r.rays.resize(n);
    r.changed.assign(n, 0);
    r.dlen.assign(n, 0.0);
}

/// The volume change (cells^3, mean of the three sets) of the moved rays re-sampled as `fixed` (varies == false)
/// and `var` (varies == true), summed per set in the rays' order.
double volume_change(std::span<const ClayMovedRay> moved, const ClayResampled& fixed, const ClayResampled& var) {
    double dv[3] = {0.0, 0.0, 0.0};
    for (std::size_t k = 0; k < moved.size(); ++k) {
        const ClayResampled& r = moved[k].varies ? var : fixed;
        if (r.changed[k]) dv[moved[k].set] += r.dlen[k];
    }
    return (dv[0] + dv[1] + dv[2]) / 3.0;
}

/// The field's volume indicator at a node: the share (0..1) of the node's cell-sized column element that lies
/// inside for signed distance p, a linear ramp over one cell (the size of what s0 moves, for the tolerance).
float ramp(float p) { return std::clamp(0.5f - p, 0.0f, 1.0f); }

/// How close (cells^3) to no change the volume must come: 1% of what s0 moved (field measure) or a hundredth of a
/// cell^3, whichever is larger.
double volume_tolerance(const ClayField& f, std::span<const ClayMovedNode> nodes) {
    double dent = 0.0;  // field volume change of s0 alone
    for (const ClayMovedNode& m : nodes) {
        const std::size_t i = m.x;
        if (f.s0[i] != 0.0f) dent += static_cast<double>(ramp(f.phi[i] + f.s0[i])) - ramp(f.phi[i]);
    }
    return std::max(0.01 * std::fabs(dent), 0.01);
}

/// beta that changes the model's own volume (the mean of the three sets' interval lengths) in the box by `target`
/// (cells^3; 0: keeps it), from b1 (the volume model's solution) whose re-sampling `best` (and `fixed`) already holds
/// with its measured change best_dv: while the measured change misses the target by more than `tolerance`
/// (volume_tolerance), up to two more re-samplings at the beta where the model, shifted by its error at the last beta
/// tried, predicts the target; the beta with the smallest miss wins and its re-sampled rays are left in `best`
/// (written without re-sampling again).
float solve_measured(std::span<const ClayMovedRay> moved, const ClayVolumeModel& vm, float b1, double target,
                     double tolerance, const ClayResampleFn& resample, const ClayResampled& fixed,
                     ClayResampled& best, double& best_dv) {
    float best_beta = b1;
    thread_local ClayResampled trial;
    float b = b1;
    double dv = best_dv;
    for (int k = 0; k < 2 && std::fabs(dv - target) > tolerance; ++k) {
        const double error = vm.change(b) - dv;  // the model's error at b, taken as constant
        // A model this close already put beta where it predicts the least change: the miss is a jump (a node's
        // status flipping) that no beta within the resolution avoids.
        if (std::fabs(error) <= 0.25 * tolerance) break;
        const float nb = vm.solve(target + error, 0.25 * tolerance);
        if (nb == b) break;
        prepare(trial, moved.size());
        resample(moved, nb, nullptr, trial);
        const double ndv = volume_change(moved, fixed, trial);
        if (std::fabs(ndv - target) < std::fabs(best_dv - target)) {
            std::swap(best, trial);
            best_beta = nb;
            best_dv = ndv;
        }
        b = nb;
        dv = ndv;
    }
    return best_beta;
}

}  // namespace

ClayStats clay_resample(TriDexel& model, const ClayField& f, bool volume_preserving, std::vector<RayImage>* before) {
    return clay_resample_with(
        model, f, volume_preserving, before,
        [&](std::span<const ClayMovedRay> moved, float beta, ClayResampled* fixed, ClayResampled& var) {
            clay_resample_on_cpu(model, f, moved, beta, fixed, var);
        });
}

ClayStats clay_resample_with(TriDexel& model, const ClayField& f, bool volume_preserving,
                             std::vector<RayImage>* before, const ClayResampleFn& resample,
                             std::vector<ClayRayRef>* written) {
    ClayStats st;
    if (f.box.empty()) return st;
    thread_local std::vector<ClayMovedNode> nodes;
    clay_moved_nodes(f, nodes);
    if (nodes.empty()) return st;
    bool any1 = false;
    for (const ClayMovedNode& m : nodes) any1 |= f.s1[m.x] != 0.0f;
    thread_local std::vector<ClayMovedRay> moved;
    clay_moved_rays(model, f, nodes, moved);
    thread_local ClayResampled fixed, var;
    prepare(fixed, moved.size());
    prepare(var, moved.size());
    // The rays that do not depend on beta once, with the first beta's re-sampling of the others.
    float beta = 0.0f;
    thread_local ClayVolumeModel vm;
    double tolerance = 0.0;
    if (volume_preserving && any1) {
        tolerance = volume_tolerance(f, nodes);
        vm.build(model, f, moved);
        beta = vm.solve(f.volume_target, 0.25 * tolerance);
    }
    resample(moved, beta, &fixed, var);
    double dv = volume_change(moved, fixed, var);
    if (volume_preserving && any1)
        beta = solve_measured(moved, vm, beta, f.volume_target, tolerance, resample, fixed, var, dv);
    for (const ClayMovedNode& m : nodes)
        st.max_displacement_cells =
            std::max(st.max_displacement_cells, static_cast<double>(std::fabs(f.s0[m.x] + beta * f.s1[m.x])));
    st.beta = beta;
    st.volume_change_cells = dv;
    for (int a = 0; a < 3; ++a)
        st.rays.rays_visited += static_cast<std::size_t>(f.box.n((a + 1) % 3)) * f.box.n((a + 2) % 3);
    ChangedBox changed;  // the ends that differ: what the contour must redo around
    for (std::size_t k = 0; k < moved.size(); ++k) {
        ClayResampled& r = moved[k].varies ? var : fixed;
        if (!r.changed[k]) continue;
        ++st.rays.rays_changed;
        std::vector<Interval>& ray = model.sets[moved[k].set].rays[moved[k].index];
        if (before) before->push_back({moved[k].set, moved[k].index, ray});
        if (written) written->push_back({moved[k].set, moved[k].index});
        const RaySet& set = model.sets[moved[k].set];
        changed.add_ray(set.axis, static_cast<int>(moved[k].index % static_cast<std::uint32_t>(set.nu)),
                        static_cast<int>(moved[k].index / static_cast<std::uint32_t>(set.nu)),
                        changed_span(ray, r.rays[k]));
        ray.swap(r.rays[k]);
    }
    changed.mark(model);
    return st;
}


}  // namespace tridex::compute
