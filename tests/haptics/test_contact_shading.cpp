// Force shading (Popescu et al. 3.2): vertex normals at dexel ends, and a HIP swept across a roof's
// ridge whose force direction turns smoothly with shading and jumps without.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <utility>

#include "haptics/forces/force_shading.hpp"
#include "haptics/god_object.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

using test::fill_set;
using test::Intervals;
using test::make_surface;

constexpr double kH = 1e-3;   // cell, m
constexpr double kDt = 1e-3;  // s
constexpr float kC = 20.25f;  // roof ridge height, cells

Vec3 mm(double x, double y, double z) { return Vec3(x, y, z) * 1e-3; }

TEST(ForceShading, VertexNormalOfAPlaneIsExact) {
    // z = 10 + 0.5 x - 0.25 y (cells) on Z rays: depths are exact in float, so the normal is exact.
    auto s = make_surface(kH);
    fill_set(*s, 2, 0, 0, [](int x, int y) { return Intervals{{0.0f, 10.0f + 0.5f * x - 0.25f * y}}; });
    const Vec3 exact = glm::normalize(Vec3(-0.5, 0.25, 1.0));
    const ActiveSurface::Window& w = s->sets[2];
    for (const auto& [iu, iv] : {std::pair{5, 7}, std::pair{0, 0}, std::pair{31, 31}, std::pair{0, 31}}) {
        const Vec3 n = dexel_end_normal(*s, 2, iu, iv, w.exit(iu, iv, 0), true);  // one-sided at the borders
        EXPECT_NEAR(n.x, exact.x, 1e-15);
        EXPECT_NEAR(n.y, exact.y, 1e-15);
        EXPECT_NEAR(n.z, exact.z, 1e-15);
    }
    // The enter ends of the same rays (solid above the plane) face the other way.
    auto above = make_surface(kH);
    fill_set(*above, 2, 0, 0, [](int x, int y) { return Intervals{{10.0f + 0.5f * x - 0.25f * y, 60.0f}}; });
    const Vec3 n = dexel_end_normal(*above, 2, 5, 7, above->sets[2].enter(5, 7, 0), false);
    EXPECT_NEAR(glm::length(n + exact), 0.0, 1e-15);
    // A step of more than kShadingMaxStepCells is another sheet: one-sided from the other neighbour.
    auto step = make_surface(kH);
    fill_set(*step, 2, 0, 0, [](int x, int) { return Intervals{{0.0f, x <= 10 ? 10.0f + 0.5f * x : 30.0f}}; });
    const Vec3 m = dexel_end_normal(*step, 2, 10, 4, 15.0, true);
    EXPECT_NEAR(m.x, glm::normalize(Vec3(-0.5, 0.0, 1.0)).x, 1e-15);
}

TEST(ForceShading, RotateBetweenKeepsLengthAndMapsTheNormal) {
    const Vec3 a = glm::normalize(Vec3(0.0, 0.0, 1.0)), b = glm::normalize(Vec3(0.3, -0.2, 1.0));
    const Vec3 t(0.7, 0.1, 0.0);  // tangential to a
    const Vec3 rt = rotate_between(a, b, t);
    EXPECT_NEAR(glm::length(rt), glm::length(t), 1e-15);
    EXPECT_NEAR(glm::dot(rt, b), 0.0, 1e-15);  // still tangential
    EXPECT_NEAR(glm::length(rotate_between(a, b, a) - b), 0.0, 1e-15);
}

// Roof over x with its ridge at x = 16 (cells): z = kC - s*|x - 16|, solid below, on Z rays.
std::unique_ptr<ActiveSurface> roof(double slope) {
    auto s = make_surface(kH);
    fill_set(*s, 2, 0, 0, [=](int x, int) { return Intervals{{0.0f, static_cast<float>(kC - slope * std::abs(x - 16))}}; });
    return s;
}

struct Sweep {
    double max_turn = 0.0;      // largest change of the force direction between ticks, rad
    double max_normal_gap = 0;  // largest angle between the force and the active triangle's normal, rad
    int contact_ticks = 0;
};

// The HIP 0.3 cell under the roof (penetration small against the facets, the regime force shading is
// for), swept from x = 12 to 20 at 0.02 cell per tick.
Sweep sweep(const ActiveSurface& s, double slope, bool shading) {
    ContactParams p{700.0, 0.0, 0.0};
    p.force_shading = shading;
    GodObject g(p);
    g.update(s, mm(12.0, 10.3, kC + 2.0), kDt);
    Sweep out;
    Vec3 last(0.0);
    for (int k = 0; k <= 400; ++k) {
        const double x = 12.0 + 0.02 * k;
        const ContactResult c = g.update(s, mm(x, 10.3, kC - slope * std::abs(x - 16.0) - 0.3), kDt);
        if (!c.contact) continue;
        ++out.contact_ticks;
        const Vec3 dir = glm::normalize(c.force_n);
        if (last != Vec3(0.0)) out.max_turn = std::max(out.max_turn, std::acos(std::clamp(glm::dot(dir, last), -1.0, 1.0)));
        out.max_normal_gap = std::max(out.max_normal_gap, std::acos(std::clamp(glm::dot(dir, c.plane_normal), -1.0, 1.0)));
        last = dir;
    }
    return out;
}

TEST(ForceShading, ForceDirectionDoesNotJumpAtARidge) {
    const double slope = 0.6;
    const auto s = roof(slope);
    const double face = std::atan(slope);  // each face's tilt from +z: the ridge turns the normal by 2x this
    const Sweep on = sweep(*s, slope, true), off = sweep(*s, slope, false);
    std::printf("ridge sweep (faces +-%.1f deg): per-tick turn of the force %.2f deg with shading, %.2f deg "
                "without; force up to %.1f deg from the facet normal with shading\n",
                face * 180 / std::numbers::pi, on.max_turn * 180 / std::numbers::pi, off.max_turn * 180 / std::numbers::pi, on.max_normal_gap * 180 / std::numbers::pi);
    EXPECT_EQ(on.contact_ticks, 401);
    EXPECT_EQ(off.contact_ticks, 401);
    // Without shading the direction jumps by the full ridge angle at one tick.
    EXPECT_NEAR(off.max_turn, 2.0 * face, 1e-6);
    // With shading it turns by one face angle over each of the two cells next to the ridge (50 ticks
    // each): about face/50 = 0.6 degree per tick, never more than 2 degrees.
    const double bound = 2.0 * std::numbers::pi / 180.0;
    EXPECT_LT(on.max_turn, bound);
    EXPECT_GT(off.max_turn, 10.0 * bound);
    // Shading turns the force at most to the vertex normals, i.e. by at most one face angle.
    EXPECT_LE(on.max_normal_gap, face + 1e-6);
}

}  // namespace
}  // namespace tridex::haptics
