// Tests of the clay volume model: its predicted volume change against the re-sampling's own measure at many beta, on
// a push's and a smooth's field, and the beta it solves keeping the volume after one re-sampling.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "clay_test_models.hpp"
#include "compute/tools/clay_kernel.hpp"
#include "compute/tools/clay_push.hpp"
#include "compute/tools/clay_resample.hpp"
#include "compute/tools/clay_volume_model.hpp"

namespace tridex::compute {
namespace {

using clay_test::cube_lattice;
using clay_test::from_implicit;

/// The volume change (cells^3, mean of the three sets) clay_resample_on_cpu measures for `moved` at beta.
double measured_change(const TriDexel& m, const ClayField& f, const std::vector<ClayMovedRay>& moved, float beta) {
    ClayResampled fixed, var;
    for (ClayResampled* r : {&fixed, &var}) {
        r->rays.resize(moved.size());
        r->changed.assign(moved.size(), 0);
        r->dlen.assign(moved.size(), 0.0);
    }
    clay_resample_on_cpu(m, f, moved, beta, &fixed, var);
    double dv = 0.0;
    for (std::size_t k = 0; k < moved.size(); ++k) dv += (moved[k].varies ? var : fixed).dlen[k];
    return dv / 3.0;
}

/// A noisy sphere (radius 14 about (24.3, 23.8, 24.1), a few tenths of a cell of bumps) on a 48-cell lattice.
TriDexel bumpy_sphere() {
    return from_implicit(cube_lattice(48), [](double x, double y, double z) {
        const double dx = x - 24.3, dy = y - 23.8, dz = z - 24.1;
        const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
        return r - 14.0 - 0.3 * std::sin(1.3 * x) * std::cos(1.1 * y) * std::sin(0.9 * z);
    });
}

/// A push field on the sphere's top: stamps along a short path pressed 0.8 cell in.
ClayField push_field(const TriDexel& m) {
    ClayStampParams p;
    const float R = 3.0f;
    p.r = kClayInfluence * R;
    p.w = kClayRimWidth * p.r;
    p.reach2 = (p.r + p.w) * (p.r + p.w) * 1.0001f;
    std::vector<ClayStamp> stamps;
    for (int k = 0; k < 5; ++k) {
        const ClayContact ct = clay_contact(m, 22.3f + 0.5f * k, 23.8f, 24.1f + 14.0f + R - 0.8f, R);
        stamps.push_back({{ct.point[0], ct.point[1], ct.point[2]}, {ct.normal[0], ct.normal[1], ct.normal[2]},
                          std::min(ct.delta, kClayMaxStep)});
    }
    ClayField f;
    const float lo[3] = {22.0f, 23.0f, 36.0f}, hi[3] = {25.0f, 24.5f, 38.5f};
    f.box = clay_support_box(lo, hi, p.r + p.w, clay_whole_box(m.lattice));
    for (int a = 0; a < 3; ++a) f.region.c[a] = stamps.front().p[a], f.region.c1[a] = stamps.back().p[a];
    f.region.r = p.r + p.w + 2.0f;
    clay_cpu_kernel().stamp_field(m, f, stamps, p);
    return f;
}

/// A smooth field at the sphere's top.
ClayField smooth_field(const TriDexel& m) {
    const ClayContact ct = clay_contact(m, 24.3f, 23.8f, 24.1f + 14.0f + 2.5f, 3.0f);
    ClaySmoothParams p;
    for (int a = 0; a < 3; ++a) p.point[a] = ct.point[a], p.normal[a] = ct.normal[a];
    p.r = kClayInfluence * 3.0f;
    ClayField f;
    f.box = clay_support_box(ct.point, ct.point, p.r, clay_whole_box(m.lattice));
    f.region.ball(ct.point, p.r + 1.01f);
    clay_cpu_kernel().smooth_field(m, f, std::span<const ClaySmoothParams>(&p, 1));
    return f;
}

void check_prediction(const TriDexel& m, const ClayField& f, const char* what) {
    std::vector<ClayMovedNode> nodes;
    clay_moved_nodes(f, nodes);
    std::vector<ClayMovedRay> moved;
    clay_moved_rays(m, f, nodes, moved);
    ASSERT_GT(moved.size(), 20u) << what;
    ClayVolumeModel vm;
    vm.build(m, f, moved);
    EXPECT_GT(vm.varying_edges(), 0u) << what;
    double worst = 0.0, span = 0.0;
    for (float beta = -kClayMaxBeta; beta <= kClayMaxBeta; beta += 0.37f) {
        const double predicted = vm.change(beta), measured = measured_change(m, f, moved, beta);
        worst = std::max(worst, std::fabs(predicted - measured));
        span = std::max(span, std::fabs(measured));
        EXPECT_NEAR(predicted, measured, 1e-3) << what << " at beta " << beta;
    }
    EXPECT_GT(span, 1.0) << what << ": the change must depend on beta for the test to mean anything";
    // The solved beta keeps the volume after one re-sampling.
    const float beta = vm.solve(0.0, 1e-3);
    const double after = measured_change(m, f, moved, beta);
    std::printf("%s: %zu moved rays, %zu edges depend on beta, worst prediction error %.2e cells^3 over a change "
                "of up to %.2f; solved beta %.4f leaves %.2e cells^3\n",
                what, moved.size(), vm.varying_edges(), worst, span, beta, after);
    EXPECT_LT(std::fabs(after), 0.05) << what;
}

TEST(ClayVolumeModel, PredictsThePushsMeasuredChangeAtEveryBeta) {
    const TriDexel m = bumpy_sphere();
    check_prediction(m, push_field(m), "push");
}

TEST(ClayVolumeModel, PredictsTheSmoothsMeasuredChangeAtEveryBeta) {
    const TriDexel m = bumpy_sphere();
    check_prediction(m, smooth_field(m), "smooth");
}

TEST(ClayVolumeModel, NoMovedRaysPredictNoChange) {
    const TriDexel m = bumpy_sphere();
    ClayField f;
    f.box = clay_whole_box(m.lattice);
    ClayVolumeModel vm;
    vm.build(m, f, {});
    EXPECT_EQ(vm.change(1.0f), 0.0);
    EXPECT_EQ(vm.varying_edges(), 0u);
    EXPECT_EQ(vm.solve(0.0, 1e-3), 0.0f);
}

}  // namespace
}  // namespace tridex::compute
