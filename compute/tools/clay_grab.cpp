// compute/tools/clay_grab.cpp - grab: the clay field advected by a falloff of the tool's motion.
#include "compute/tools/clay_grab.hpp"

#include <algorithm>
#include <cmath>

#include "compute/tools/clay_push.hpp"

namespace tridex::compute {

void clay_grab_offsets(const TriDexel& model, ClayField& field, const ClayGrabParams& p) {
    const float r2 = p.r * p.r;
    clay_for_each_movable_node(model, field, [&](int ix, int jy, int kz, std::size_t i) {
        const float dx = static_cast<float>(ix) - p.anchor[0], dy = static_cast<float>(jy) - p.anchor[1],
                    dz = static_cast<float>(kz) - p.anchor[2];
        const float d2 = dx * dx + dy * dy + dz * dz;
        if (!(d2 < r2)) return;
        const float w = clay_grab_falloff(std::sqrt(d2), p.core, p.r);
        const float qx = static_cast<float>(ix) - w * p.v[0], qy = static_cast<float>(jy) - w * p.v[1],
                    qz = static_cast<float>(kz) - w * p.v[2];
        const float s0 = clay_phi_at(field, qx, qy, qz) - field.phi[i];
        field.s0[i] = s0;
        const float psi = field.phi[i] + s0;
        if (std::fabs(psi) < kClayMaxBeta + 1.0f) field.s1[i] = w;
    });
}

double clay_grab_volume_change(const TriDexel& model, const ClayField& field, const ClayGrabParams& p) {
    double dv = 0.0;
    const double c = p.core, r = p.r;
    clay_for_each_movable_node(model, field, [&](int ix, int jy, int kz, std::size_t i) {
        const double x[3] = {ix - static_cast<double>(p.anchor[0]), jy - static_cast<double>(p.anchor[1]),
                             kz - static_cast<double>(p.anchor[2])};
        const double d = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        if (!(d > c) || !(d < r)) return;  // w' = 0 in the core and beyond r
        const double inside = std::clamp(0.5 - static_cast<double>(field.phi[i]), 0.0, 1.0);
        if (inside == 0.0) return;
        const double t = (d - c) / (r - c);
        const double dw = -4.0 * t * (1.0 - t * t) / (r - c);  // dw/dd
        dv += inside * dw * (x[0] * p.v[0] + x[1] * p.v[1] + x[2] * p.v[2]) / d;
    });
    return dv;
}

ClayStats clay_grab(TriDexel& model, const GridSweep& g, std::vector<RayImage>* before, ClayKernel& kernel) {
    const float R = g.radius;
    float a[3];
    for (int k = 0; k < 3; ++k) a[k] = static_cast<float>(g.origin[k]) + g.start[k];
    const float len = std::sqrt(g.delta[0] * g.delta[0] + g.delta[1] * g.delta[1] + g.delta[2] * g.delta[2]);
    if (!(len > 0.0f)) return {};
    // Only a ball touching material where the motion starts grips it, at the surface point under it.
    const ClayContact ct = clay_contact(model, a[0], a[1], a[2], R);
    if (!(ct.delta >= -kClayGrabGrip)) return {};
    const float step = std::min(kClayGrabStepCells, 0.5f * R);
    const int n = static_cast<int>(std::min(std::ceil(len / step), 1.0e6f));
    ClayGrabParams p;
    p.core = kClayGrabCore * R;
    p.r = kClayGrabInfluence * R;
    for (int k = 0; k < 3; ++k) p.v[k] = g.delta[k] / static_cast<float>(n);
    const float vlen = len / static_cast<float>(n);
    const ClayBox outer = clay_sweeps_box(std::span<const GridSweep>(&g, 1));
    ClayStats total;
    ClayField field;  // every step rebuilds its arrays in place (clay_build_phi), reusing their memory
    for (int s = 0; s < n; ++s) {
        // The grabbed point moves with the material it holds: step s starts where the steps before it left it.
        const float f = static_cast<float>(s);
        for (int k = 0; k < 3; ++k) p.anchor[k] = ct.point[k] + p.v[k] * f;
        // The nodes that move lie within r of the anchor; their lookups x - u and its 8 nodes within r + |v| + 2.
        const float reach = p.r + vlen + 2.0f;
        field.box = clay_support_box(p.anchor, p.anchor, reach, outer);
        if (field.box.empty()) continue;
        field.region.ball(p.anchor, reach + 0.01f);
        kernel.grab_field(model, field, p);
        field.volume_target = clay_grab_volume_change(model, field, p);
        const ClayStats st = kernel.resample(model, field, before);
        total.rays.rays_visited += st.rays.rays_visited;
        total.rays.rays_changed += st.rays.rays_changed;
        total.volume_change_cells += st.volume_change_cells;
        total.max_displacement_cells = std::max(total.max_displacement_cells, st.max_displacement_cells);
        total.beta = st.beta;  // the last step's
    }
    return total;
}

}  // namespace tridex::compute
