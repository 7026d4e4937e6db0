// compute/tools/clay_smooth.cpp - volume-keeping steps of the node field's Laplacian flow under the tool.
#include "compute/tools/clay_smooth.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "compute/tools/clay_push.hpp"
#include "core/error.hpp"

namespace tridex::compute {

void clay_smooth_offsets(const TriDexel& model, ClayField& field, std::span<const ClaySmoothParams> acts) {
    const ClayBox& b = field.box;
    // The nodes any act may move: movable, in the region, within 2 cells of the surface (phi, not psi, so the band
    // is the same for every act). Each act visits only these.
    thread_local std::vector<std::array<int, 3>> band;
    thread_local std::vector<std::size_t> band_at;
    // The band's x-rows in order: (jy, kz, first band index); one past the last row closes the list.
    thread_local std::vector<std::array<int, 3>> rows;
    band.clear();
    band_at.clear();
    rows.clear();
    clay_for_each_movable_node(model, field, [&](int ix, int jy, int kz, std::size_t i) {
        if (!(std::fabs(field.phi[i]) < 2.0f)) return;
        if (rows.empty() || rows.back()[0] != jy || rows.back()[1] != kz)
            rows.push_back({jy, kz, static_cast<int>(band.size())});
        band.push_back({ix, jy, kz});
        band_at.push_back(i);
    });
    rows.push_back({0, 0, static_cast<int>(band.size())});
    const std::size_t sy = b.stride(1), sz = b.stride(2);
    const auto psi = [&](std::size_t x) { return field.phi[x] + field.s0[x]; };
    thread_local std::vector<std::pair<std::size_t, float>> step;
    for (const ClaySmoothParams& p : acts) {
        const float r = p.r;
        // No node with d^2 at or above this has sqrt(d^2) < r in float (r^2 rounded up with room to spare): the
        // square root is skipped there with the same outcome.
        const float r2_far = r * r * 1.001f;
        step.clear();
        for (std::size_t row = 0; row + 1 < rows.size(); ++row) {
            // A row whose line passes r or more from the act's point has no node within reach: skipped whole (the
            // per-node test below would reject each of its nodes the same way).
            const float ry = static_cast<float>(rows[row][0]) - p.point[1],
                        rz = static_cast<float>(rows[row][1]) - p.point[2];
            if (!(ry * ry + rz * rz < r2_far)) continue;
            const std::size_t k0 = static_cast<std::size_t>(rows[row][2]), k1 = static_cast<std::size_t>(rows[row + 1][2]);
            for (std::size_t k = k0; k < k1; ++k) {
                const std::size_t i = band_at[k];
                const float dx = static_cast<float>(band[k][0]) - p.point[0],
                            dy = static_cast<float>(band[k][1]) - p.point[1],
                            dz = static_cast<float>(band[k][2]) - p.point[2];
                const float d2 = dx * dx + dy * dy + dz * dz;
                if (!(d2 < r2_far)) continue;
                const float d = std::sqrt(d2);
                if (!(d < r)) continue;
                const float depth = -(dx * p.normal[0] + dy * p.normal[1] + dz * p.normal[2]);
                if (depth > clay_sheet_depth(0.0f, d)) continue;  // another sheet of the solid
                const float x = d / r;
                const float wgt = 1.0f - x * x;  // Popescu 3.3 falloff within the radius of influence
                const float lap = psi(i - 1) + psi(i + 1) + psi(i - sy) + psi(i + sy) + psi(i - sz) + psi(i + sz) -
                                  6.0f * psi(i);
                step.emplace_back(i, kClaySmoothRate * wgt * lap);
                field.s1[i] = std::max(field.s1[i], wgt);
            }
        }
        for (const auto& [i, s] : step) field.s0[i] = field.s0[i] + s;
    }
}

ClayStats clay_smooth(TriDexel& model, const GridSweep& g, std::vector<RayImage>* before, ClayKernel& kernel) {
    return clay_smooth_group(model, std::span<const GridSweep>(&g, 1), before, kernel);
}

ClayStats clay_smooth_group(TriDexel& model, std::span<const GridSweep> sweeps, std::vector<RayImage>* before,
                            ClayKernel& kernel) {
    if (sweeps.empty()) return {};
    const float R = sweeps[0].radius, r = kClayInfluence * R;
    thread_local std::vector<ClaySmoothParams> acts;
    acts.clear();
    for (const GridSweep& g : sweeps) {
        if (g.radius != R) throw Error("clay smooth group: the sweeps' tool radii differ");
        // Once per half-cell plane crossed by the motion a -> b.
        bool crosses = false;
        float c[3];
        for (int a = 0; a < 3; ++a) {
            const float sa = g.start[a], se = g.start[a] + g.delta[a];
            crosses |= std::floor(2.0f * sa) != std::floor(2.0f * se);
            c[a] = static_cast<float>(g.origin[a]) + se;
        }
        if (!crosses) continue;
        const ClayContact ct = clay_contact(model, c[0], c[1], c[2], R);  // against the model before the group
        if (!(ct.phi <= R + 0.5f)) continue;
        ClaySmoothParams p;
        for (int a = 0; a < 3; ++a) p.point[a] = ct.point[a], p.normal[a] = ct.normal[a];
        p.r = r;
        acts.push_back(p);
    }
    if (acts.empty()) return {};
    ClayField field;
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = hi[a] = acts[0].point[a];
        for (const ClaySmoothParams& p : acts) lo[a] = std::min(lo[a], p.point[a]), hi[a] = std::max(hi[a], p.point[a]);
    }
    field.box = clay_support_box(lo, hi, r, clay_sweeps_box(sweeps));  // around the contact points
    if (field.box.empty()) return {};
    // The narrow region: the nodes within r of a contact point (the only ones that move) and their neighbours; for
    // several acts a capsule from the first contact point to the last, widened by the farthest point's distance.
    if (acts.size() == 1) {
        field.region.ball(acts[0].point, r + 1.01f);  // a neighbour lies within 1 cell of a moved node
    } else {
        for (int a = 0; a < 3; ++a) field.region.c[a] = acts.front().point[a], field.region.c1[a] = acts.back().point[a];
        float off2 = 0.0f;
        for (const ClaySmoothParams& p : acts)
            off2 = std::max(off2, field.region.distance2(p.point[0], p.point[1], p.point[2]));
        field.region.r = r + 1.01f + std::sqrt(off2) * 1.0001f + 1e-3f;
    }
    kernel.smooth_field(model, field, acts);
    return kernel.resample(model, field, before);
}

}  // namespace tridex::compute
