// compute/tools/clay_push.cpp - plastic push with Popescu's radius of influence and a volume-preserving rim.
#include "compute/tools/clay_push.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "compute/tools/clay_sweep.hpp"
#include "core/error.hpp"

namespace tridex::compute {
namespace {

/// The rim's bump on x in [0, 1]: (4x(1-x))^2, 0 with zero slope at both ends, 1 at x = 1/2.
float rim_bump(float x) {
    const float b = 4.0f * x * (1.0f - x);
    return b * b;
}

}  // namespace

float clay_surface_distance(const TriDexel& model, float cx, float cy, float cz, float search) {
    const float c[3] = {cx, cy, cz};
    float best2 = search * search;
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = model.sets[a];
        const int ua = (a + 1) % 3, va = (a + 2) % 3;
        const int u0 = std::max(0, static_cast<int>(std::ceil(c[ua] - search)));
        const int u1 = std::min(set.nu - 1, static_cast<int>(std::floor(c[ua] + search)));
        const int v0 = std::max(0, static_cast<int>(std::ceil(c[va] - search)));
        const int v1 = std::min(set.nv - 1, static_cast<int>(std::floor(c[va] + search)));
        for (int v = v0; v <= v1; ++v) {
            const float dv = static_cast<float>(v) - c[va];
            for (int u = u0; u <= u1; ++u) {
                const float du = static_cast<float>(u) - c[ua];
                const float side2 = du * du + dv * dv;
                if (!(side2 < best2)) continue;
                for (const Interval& iv : set.ray(u, v)) {
                    const float e = iv.enter - c[a], x = iv.exit - c[a];
                    best2 = std::min(best2, side2 + e * e);
                    best2 = std::min(best2, side2 + x * x);
                    if (x > 0.0f && e > 0.0f) break;  // later crossings lie farther along the ray
                }
            }
        }
    }
    return std::sqrt(best2);
}

ClayBox clay_sweeps_box(std::span<const GridSweep> sweeps) {
    ClayBox b;
    for (std::size_t k = 0; k < sweeps.size(); ++k)
        for (int a = 0; a < 3; ++a) {
            b.lo[a] = k == 0 ? sweeps[k].lo[a] : std::min(b.lo[a], sweeps[k].lo[a]);
            b.hi[a] = k == 0 ? sweeps[k].hi[a] : std::max(b.hi[a], sweeps[k].hi[a]);
        }
    return b;
}

ClayContact clay_contact(const TriDexel& model, float cx, float cy, float cz, float r_cells) {
    thread_local ClayField f;  // its arrays' storage kept from call to call
    const float c[3] = {cx, cy, cz};
    for (int a = 0; a < 3; ++a) {
        const int b = static_cast<int>(std::floor(c[a]));
        f.box.lo[a] = std::clamp(b - 1, 0, model.lattice.cells[a]);
        f.box.hi[a] = std::clamp(b + 2, 0, model.lattice.cells[a]);
    }
    f.search = std::max(static_cast<float>(kClaySearchCells), r_cells + 2.0f);  // a large tool's contact lies far out
    ClayContact k;
    if (f.box.empty()) {
        k.phi = f.search;
        k.delta = r_cells - k.phi;
        for (int a = 0; a < 3; ++a) k.point[a] = c[a];
        return k;
    }
    // phi at the box's few nodes one by one (clay_node_phi: the values clay_build_phi gives, without its set-up).
    f.phi.resize(f.box.count());
    for (int kz = f.box.lo[2]; kz <= f.box.hi[2]; ++kz)
        for (int jy = f.box.lo[1]; jy <= f.box.hi[1]; ++jy)
            for (int ix = f.box.lo[0]; ix <= f.box.hi[0]; ++ix)
                f.phi[f.box.index(ix, jy, kz)] = clay_node_phi(model, ix, jy, kz, f.search);
    k.phi = clay_phi_at(f, cx, cy, cz);
    // Outside, the distance to the nearest crossing: the field's plane-exact distance mixes crossings of different
    // surfaces (a rim beside a dent's floor) and would report the tool closer than it is.
    if (k.phi > 0.0f) k.phi = clay_surface_distance(model, cx, cy, cz, f.search);
    k.delta = r_cells - k.phi;
    float g[3];
    for (int a = 0; a < 3; ++a) {
        float p1[3] = {cx, cy, cz}, p0[3] = {cx, cy, cz};
        p1[a] += 0.5f;
        p0[a] -= 0.5f;
        g[a] = clay_phi_at(f, p1[0], p1[1], p1[2]) - clay_phi_at(f, p0[0], p0[1], p0[2]);
    }
    const float len = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    const float reach = std::max(k.phi, 0.0f);
    for (int a = 0; a < 3; ++a) {
        k.normal[a] = len > 0.0f ? g[a] / len : 0.0f;
        k.point[a] = c[a] - reach * k.normal[a];
    }
    return k;
}

namespace {

// The displacement field of a push (inward = true) or a pull (inward = false) from its interaction points, applied
// with a volume-keeping rim (push) or moat (pull) by `kernel`. `outer` bounds the nodes that may change (the union
// of the sweeps' lo..hi); R is the ball's radius, cells.
ClayStats apply_stamps(TriDexel& model, const ClayBox& outer, float R, const std::vector<ClayStamp>& stamps,
                       bool inward, std::vector<RayImage>* before, ClayKernel& kernel) {
    if (stamps.empty()) return {};
    ClayStampParams params;
    params.r = kClayInfluence * R;
    params.w = kClayRimWidth * params.r;
    params.reach2 = (params.r + params.w) * (params.r + params.w) * 1.0001f;  // with rounding to spare
    params.sign = inward ? 1.0f : -1.0f;
    params.rim_cap = kClayMaxStep;
    const float r = params.r, w = params.w;
    ClayField field;
    // The box around the contact points (the sweeps' lo..hi allow for any contact within R + 0.5 of the centre).
    float plo[3], phi_[3];
    for (int a = 0; a < 3; ++a) {
        plo[a] = stamps[0].p[a], phi_[a] = stamps[0].p[a];
        for (const ClayStamp& s : stamps) plo[a] = std::min(plo[a], s.p[a]), phi_[a] = std::max(phi_[a], s.p[a]);
    }
    field.box = clay_support_box(plo, phi_, r + w, outer);
    if (field.box.empty()) return {};
    // The narrow region: the nodes within r + w of a contact point (the only ones that move) and their neighbours,
    // as a capsule from the first contact point to the last, widened by the farthest point's distance from it.
    for (int a = 0; a < 3; ++a) field.region.c[a] = stamps.front().p[a], field.region.c1[a] = stamps.back().p[a];
    float off2 = 0.0f;
    for (const ClayStamp& s : stamps) off2 = std::max(off2, field.region.distance2(s.p[0], s.p[1], s.p[2]));
    field.region.r = r + w + 1.01f + std::sqrt(off2) * 1.0001f + 1e-3f;  // a neighbour lies within 1 cell of a moved node
    kernel.stamp_field(model, field, stamps, params);
    return kernel.resample(model, field, before);
}

// The ball's centre (grid units) at stamp k of n along the sweep (k = 0: the motion's start).
void stamp_centre(const GridSweep& g, std::uint32_t k, std::uint32_t n, float c[3]) {
    const float f = static_cast<float>(k) / static_cast<float>(n);
    for (int a = 0; a < 3; ++a) c[a] = static_cast<float>(g.origin[a]) + (g.start[a] + g.delta[a] * f);
}

}  // namespace

void clay_stamp_offsets(const TriDexel& model, ClayField& field, std::span<const ClayStamp> stamps,
                        const ClayStampParams& p) {
    const float r = p.r, w = p.w, reach2 = p.reach2, sign = p.sign, rim_cap = p.rim_cap;
    // No node farther from the surface than this gets an offset (a dent is at most the largest delta, a rim's weight
    // at most that and rim_cap), so the stamps need not be visited there.
    float top = 0.0f;
    for (const ClayStamp& s : stamps) top = std::max(top, s.delta);
    const float far = std::max(top, std::min(top, rim_cap) * kClayMaxBeta) + 2.0f;
    // Per x-row, the stamps within reach of the row's line: dy^2 + dz^2 <= reach2, which no node's dx^2 + dy^2 + dz^2
    // can undercut in float (rounding is monotone), so the others would be skipped anyway. The row's terms of each
    // (dy^2, dz^2, dy n_y, dz n_z) are the same floats the per-node sums below would compute.
    struct Near {
        float px, nx, dy2, dz2, dyn, dzn, delta;
    };
    thread_local std::vector<Near> near;
    int row_j = -1, row_k = -1;
    const float dent_band = top + 2.0f;  // no node this far from the surface takes a dent's s0
    clay_for_each_movable_node(model, field, [&](int ix, int jy, int kz, std::size_t i) {
        const float phi = field.phi[i];
        if (!(std::fabs(phi) < far)) return;
        const float q[3] = {static_cast<float>(ix), static_cast<float>(jy), static_cast<float>(kz)};
        if (jy != row_j || kz != row_k) {
            row_j = jy, row_k = kz;
            near.clear();
            for (const ClayStamp& s : stamps) {
                const float dy = q[1] - s.p[1], dz = q[2] - s.p[2];
                if (!(dy * dy + dz * dz > reach2))
                    near.push_back({s.p[0], s.n[0], dy * dy, dz * dz, dy * s.n[1], dz * s.n[2], s.delta});
            }
        }
        // A node outside the dent band changes only when no stamp dents it (then the rim may): it stops at the
        // first stamp that does.
        const bool dent_only_blocks = !(std::fabs(phi) < dent_band);
        float dent = 0.0f, rim = 0.0f;
        for (const Near& s : near) {
            const float dx = q[0] - s.px;
            const float d2 = dx * dx + s.dy2 + s.dz2;
            if (d2 > reach2) continue;
            const float d = std::sqrt(d2);
            const float depth = -(dx * s.nx + s.dyn + s.dzn);
            if (depth > clay_sheet_depth(s.delta, d)) continue;  // another sheet of the solid
            if (d < r) {
                const float x = d / r;
                dent = std::max(dent, s.delta * (1.0f - x * x));  // Popescu 3.3: k = 1 - (d/r)^2, the largest wins
                if (dent_only_blocks && dent > 0.0f) return;
            } else if (d < r + w) {
                rim = std::max(rim, std::min(s.delta, rim_cap) * rim_bump((d - r) / w));
            }
        }
        if (dent > 0.0f) {
            if (std::fabs(phi) < dent + 2.0f) field.s0[i] = sign * dent;
        } else if (rim > 0.0f) {
            if (std::fabs(phi) < rim * kClayMaxBeta + 2.0f) field.s1[i] = -sign * rim;
        }
    });
}

namespace {

// The ball centres (grid units) at which a push group takes its contacts: the end of every half-cell sub-step of
// every sweep (GridSweep::stamps), thinned along the path to one per clay_stamp_spacing(R) of motion, the group's last
// centre always kept (the tool's latest pose).
void clay_push_centres(std::span<const GridSweep> sweeps, std::vector<std::array<float, 3>>& centres) {
    centres.clear();
    const float h = clay_stamp_spacing(sweeps[0].radius);
    float run = 0.0f;  // motion since the last centre kept, cells
    for (std::size_t s = 0; s < sweeps.size(); ++s) {
        const GridSweep& g = sweeps[s];
        const std::uint32_t n = std::max<std::uint32_t>(g.stamps, 1u);
        float prev[3];
        stamp_centre(g, 0, n, prev);
        for (std::uint32_t k = 0; k < n; ++k) {
            float c[3];
            stamp_centre(g, k + 1, n, c);
            const float dx = c[0] - prev[0], dy = c[1] - prev[1], dz = c[2] - prev[2];
            run += std::sqrt(dx * dx + dy * dy + dz * dz);
            prev[0] = c[0], prev[1] = c[1], prev[2] = c[2];
            const bool last = s + 1 == sweeps.size() && k + 1 == n;
            if (run < h && !last) continue;
            centres.push_back({c[0], c[1], c[2]});
            run = 0.0f;
        }
    }
}

}  // namespace

float clay_stamp_spacing(float radius_cells) { return std::max(0.5f, kClayStampSpacing * radius_cells); }

ClayStats clay_push(TriDexel& model, const GridSweep& g, std::vector<RayImage>* before, ClayKernel& kernel) {
    return clay_push_group(model, std::span<const GridSweep>(&g, 1), before, kernel);
}

ClayStats clay_push_group(TriDexel& model, std::span<const GridSweep> sweeps, std::vector<RayImage>* before,
                          ClayKernel& kernel) {
    if (sweeps.empty()) return {};
    // The interaction points: the ball at each stamp of every sweep, its contact and penetration, all against the
    // model as it is before the group.
    thread_local std::vector<ClayStamp> stamps;
    stamps.clear();
    // Pushed one by one, a spot under the tool for n sweeps could sink by n steps; grouped, it sinks in one.
    const float max_step = std::min(kClayMaxStep * static_cast<float>(sweeps.size()), kClayGroupMaxStep);
    for (const GridSweep& g : sweeps)
        if (g.radius != sweeps[0].radius) throw Error("clay push group: the sweeps' tool radii differ");
    const float R = sweeps[0].radius;
    thread_local std::vector<std::array<float, 3>> centres;
    clay_push_centres(sweeps, centres);
    for (const std::array<float, 3>& c : centres) {
        const ClayContact ct = clay_contact(model, c[0], c[1], c[2], R);
        if (!(ct.delta >= kClayMinStep)) continue;
        stamps.push_back({{ct.point[0], ct.point[1], ct.point[2]},
                          {ct.normal[0], ct.normal[1], ct.normal[2]},
                          std::min(ct.delta, max_step)});
    }
    return apply_stamps(model, clay_sweeps_box(sweeps), R, stamps, true, before, kernel);
}

ClayStats clay_pull(TriDexel& model, const GridSweep& g, std::vector<RayImage>* before, ClayKernel& kernel) {
    const float R = g.radius;
    const std::uint32_t n = std::max<std::uint32_t>(g.stamps, 1u);
    // Only a tool that touches the surface where the motion starts holds on to it.
    float a[3];
    stamp_centre(g, 0, n, a);
    if (!(clay_contact(model, a[0], a[1], a[2], R).delta >= -kClayPullGrip)) return {};
    std::vector<ClayStamp> stamps;
    for (std::uint32_t k = 0; k < n; ++k) {
        float c[3];
        stamp_centre(g, k + 1, n, c);
        const ClayContact ct = clay_contact(model, c[0], c[1], c[2], R);
        const float gap = -ct.delta;  // how far the tool has drawn away from the surface, cells
        if (!(gap >= kClayMinStep)) continue;
        stamps.push_back({{ct.point[0], ct.point[1], ct.point[2]},
                          {ct.normal[0], ct.normal[1], ct.normal[2]},
                          std::min(gap, kClayPullMaxStep)});
    }
    return apply_stamps(model, clay_sweeps_box(std::span<const GridSweep>(&g, 1)), R, stamps, false, before, kernel);
}

}  // namespace tridex::compute
