// compute/tools/clay_smooth.cpp - one volume-keeping step of the node field's Laplacian flow under the tool.
#include "compute/tools/clay_smooth.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "compute/tools/clay_push.hpp"

namespace tridex::compute {

void clay_smooth_offsets(const TriDexel& model, ClayField& field, const ClaySmoothParams& p) {
    const ClayBox& b = field.box;
    const float r = p.r;
    clay_for_each_movable_node(model, field, [&](int ix, int jy, int kz, std::size_t i) {
        const float phi = field.phi[i];
        if (!(std::fabs(phi) < 2.0f)) return;
        const float dx = static_cast<float>(ix) - p.point[0], dy = static_cast<float>(jy) - p.point[1],
                    dz = static_cast<float>(kz) - p.point[2];
        const float d = std::sqrt(dx * dx + dy * dy + dz * dz);
        if (!(d < r)) return;
        const float depth = -(dx * p.normal[0] + dy * p.normal[1] + dz * p.normal[2]);
        if (depth > clay_sheet_depth(0.0f, d)) return;  // another sheet of the solid
        const float x = d / r;
        const float wgt = 1.0f - x * x;  // Popescu 3.3 falloff within the radius of influence
        const float lap = field.phi[b.index(ix - 1, jy, kz)] + field.phi[b.index(ix + 1, jy, kz)] +
                          field.phi[b.index(ix, jy - 1, kz)] + field.phi[b.index(ix, jy + 1, kz)] +
                          field.phi[b.index(ix, jy, kz - 1)] + field.phi[b.index(ix, jy, kz + 1)] - 6.0f * phi;
        field.s0[i] = kClaySmoothRate * wgt * lap;
        field.s1[i] = wgt;
    });
}

ClayStats clay_smooth(TriDexel& model, const GridSweep& g, std::vector<RayImage>* before, ClayKernel& kernel) {
    const float R = g.radius, r = kClayInfluence * R;
    // Once per half-cell plane crossed by the motion a -> b.
    bool crosses = false;
    float c[3];
    for (int a = 0; a < 3; ++a) {
        const float sa = g.start[a], sb = g.start[a] + g.delta[a];
        crosses |= std::floor(2.0f * sa) != std::floor(2.0f * sb);
        c[a] = static_cast<float>(g.origin[a]) + sb;
    }
    if (!crosses) return {};
    const ClayContact ct = clay_contact(model, c[0], c[1], c[2], R);
    if (!(ct.phi <= R + 0.5f)) return {};
    ClayField field;
    ClayBox outer;
    for (int a = 0; a < 3; ++a) outer.lo[a] = g.lo[a], outer.hi[a] = g.hi[a];
    field.box = clay_support_box(ct.point, ct.point, r, outer);  // around the contact point
    if (field.box.empty()) return {};
    // The narrow region: the nodes within r of the contact point (the only ones that move) and their neighbours.
    field.region.ball(ct.point, r + 1.01f);  // a neighbour lies within 1 cell of a moved node
    ClaySmoothParams params;
    for (int a = 0; a < 3; ++a) params.point[a] = ct.point[a], params.normal[a] = ct.normal[a];
    params.r = r;
    kernel.smooth_field(model, field, params);
    return kernel.resample(model, field, before);
}

}  // namespace tridex::compute
