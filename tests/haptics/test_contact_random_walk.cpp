// Long random walks of the HIP in and out of hand-built solids (a sphere, a box with a slot, a thin
// tilted plate), scan-converted exactly into all three ray sets of an ActiveSurface: after every tick
// the god-object's contact point must not be inside material, as the snapshot's rays see it and as the
// analytic solid says.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <utility>

#include "haptics/god_object.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

using test::fill_set;
using test::Intervals;
using test::make_surface;

constexpr double kH = 1e-3;  // cell, m
constexpr double kDt = 1e-3; // s
// Tolerances of the check, cells: the snapshot says "inside" when, in some ray set, all four rays around
// the point hold it more than kSnapshotTol inside an interval; the analytic solid when its signed
// distance is below -kAnalyticTol (the triangles cut convex edges and span concave ones by up to about
// one cell).
constexpr double kSnapshotTol = 0.5;
constexpr double kAnalyticTol = 1.0;

/// A solid in grid units: its intervals along a ray of set a through lattice node (u, v), and its
/// signed distance (negative inside).
struct Solid {
    std::string name;
    std::function<Intervals(int a, double u, double v)> rays;
    std::function<double(const Vec3& g)> sdf;
};

// Point of grid coordinates: depth d along axis a, u along (a+1)%3, v along (a+2)%3.
Vec3 grid_point(int a, double u, double v, double d) {
    Vec3 g;
    g[a] = d;
    g[(a + 1) % 3] = u;
    g[(a + 2) % 3] = v;
    return g;
}

Solid sphere() {
    const Vec3 c(16.3, 15.7, 16.2);
    const double R = 9.4;
    return {"sphere",
            [=](int a, double u, double v) {
                const double du = u - c[(a + 1) % 3], dv = v - c[(a + 2) % 3];
                const double h2 = R * R - du * du - dv * dv;
                if (h2 <= 0.0) return Intervals{};
                const double h = std::sqrt(h2);
                return Intervals{{static_cast<float>(c[a] - h), static_cast<float>(c[a] + h)}};
            },
            [=](const Vec3& g) { return glm::length(g - c) - R; }};
}

// Box [5.5, 26.5] x [5.5, 26.5] x [5.5, 20.5] minus a slot x in [14.3, 17.1], z > 12.5 through all y.
Solid box_with_slot() {
    const Vec3 lo(5.5), hi(26.5, 26.5, 20.5);
    const double sx0 = 14.3, sx1 = 17.1, sz = 12.5;
    auto in_range = [](double x, double a, double b) { return x > a && x < b; };
    return {"box with slot",
            [=](int a, double u, double v) {
                const Vec3 g = grid_point(a, u, v, 0.0);
                const int ua = (a + 1) % 3, va = (a + 2) % 3;
                if (!in_range(g[ua], lo[ua], hi[ua]) || !in_range(g[va], lo[va], hi[va])) return Intervals{};
                const auto f = [](double x) { return static_cast<float>(x); };
                if (a == 0) {  // X ray at (y, z)
                    if (g.z > sz) return Intervals{{f(lo.x), f(sx0)}, {f(sx1), f(hi.x)}};
                    return Intervals{{f(lo.x), f(hi.x)}};
                }
                if (a == 1) {  // Y ray at (z, x)
                    if (g.z > sz && in_range(g.x, sx0, sx1)) return Intervals{};
                    return Intervals{{f(lo.y), f(hi.y)}};
                }
                if (in_range(g.x, sx0, sx1)) return Intervals{{f(lo.z), f(sz)}};  // Z ray at (x, y)
                return Intervals{{f(lo.z), f(hi.z)}};
            },
            [=](const Vec3& g) {
                const Vec3 c = 0.5 * (lo + hi), e = 0.5 * (hi - lo);
                const Vec3 q = glm::abs(g - c) - e;
                const double box = glm::length(glm::max(q, Vec3(0.0))) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0);
                const Vec3 sc(0.5 * (sx0 + sx1), 16.0, 0.5 * (sz + 40.0)), se(0.5 * (sx1 - sx0), 40.0, 0.5 * (40.0 - sz));
                const Vec3 qs = glm::abs(g - sc) - se;
                const double slot =
                    glm::length(glm::max(qs, Vec3(0.0))) + std::min(std::max(qs.x, std::max(qs.y, qs.z)), 0.0);
                return std::max(box, -slot);
            }};
}

// A plate 0.45 cell thick through (16, 16, 16), tilted: normal along (0.25, -0.15, 1).
Solid thin_plate() {
    const Vec3 n = glm::normalize(Vec3(0.25, -0.15, 1.0));
    const double c0 = glm::dot(n, Vec3(16.0)), t = 0.45;
    return {"thin plate",
            [=](int a, double u, double v) {
                const double base = glm::dot(n, grid_point(a, u, v, 0.0));
                double s0 = (c0 - base) / n[a], s1 = (c0 + t - base) / n[a];
                if (s0 > s1) std::swap(s0, s1);
                if (s1 < 0.0 || s0 > 63.0) return Intervals{};
                return Intervals{{static_cast<float>(std::max(s0, 0.0)), static_cast<float>(std::min(s1, 63.0))}};
            },
            [=](const Vec3& g) {
                const double x = glm::dot(n, g);
                return std::max(c0 - x, x - (c0 + t));
            }};
}

std::unique_ptr<ActiveSurface> scan(const Solid& solid) {
    auto s = make_surface(kH);
    for (int a = 0; a < 3; ++a) fill_set(*s, a, 0, 0, [&](int u, int v) { return solid.rays(a, u, v); });
    return s;
}

// How far (cells) p (grid units) lies inside material by the test's own reading of the snapshot: the
// largest, over the ray sets, of the smallest margin by which the four rays around p hold it (0 when
// some ray does not hold it at all).
double snapshot_inside_cells(const ActiveSurface& s, const Vec3& g) {
    double worst = 0.0;
    for (int a = 0; a < 3; ++a) {
        const ActiveSurface::Window& w = s.sets[a];
        const double u = g[(a + 1) % 3] - w.u0, v = g[(a + 2) % 3] - w.v0;
        if (!(u >= 0.0 && v >= 0.0 && u <= w.nu - 1 && v <= w.nv - 1)) continue;
        const int iu = std::min(static_cast<int>(u), w.nu - 2), iv = std::min(static_cast<int>(v), w.nv - 2);
        double margin = std::numeric_limits<double>::infinity();
        for (int k = 0; k < 4; ++k) {
            const int ru = iu + (k & 1), rv = iv + (k >> 1);
            double best = 0.0;  // margin of the interval holding g[a] on this ray
            for (int n = 0; n < w.intervals(ru, rv); ++n)
                best = std::max(best, std::min(g[a] - w.enter(ru, rv, n), w.exit(ru, rv, n) - g[a]));
            margin = std::min(margin, best);
        }
        worst = std::max(worst, margin);
    }
    return worst;
}

struct WalkStats {
    int ticks = 0, contact = 0, held = 0, hip_deep = 0, failures = 0;
    double worst_snapshot = 0.0, worst_analytic = 0.0;  // cells inside
};

// A HIP that heads for random targets in [2, 29]^3 cells (inside and outside the solid) at random speeds
// up to 0.6 cell per tick, with jitter; `ticks` updates.
WalkStats random_walk(const Solid& solid, const ActiveSurface& s, double radius_cells, double mu, unsigned seed,
                      int ticks) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(2.0, 29.0), speed(0.02, 0.6);
    std::normal_distribution<double> jitter(0.0, 0.05);
    ContactParams p{700.0, 0.5, radius_cells * kH, mu, 0.7 * mu};
    GodObject g(p);
    Vec3 hip(2.5, 2.5, 2.5), target(uni(rng), uni(rng), uni(rng));
    double v = speed(rng);
    int age = 0;
    WalkStats st;
    for (int t = 0; t < ticks; ++t) {
        const Vec3 d = target - hip;
        if (glm::length(d) < v || ++age > 400) {
            target = Vec3(uni(rng), uni(rng), uni(rng));
            v = speed(rng);
            age = 0;
        } else {
            hip += d * (v / glm::length(d));
        }
        hip += Vec3(jitter(rng), jitter(rng), jitter(rng));
        hip = glm::clamp(hip, Vec3(1.0), Vec3(30.0));
        const ContactResult c = g.update(s, hip * kH, kDt);
        ++st.ticks;
        st.contact += c.contact ? 1 : 0;
        st.held += c.held ? 1 : 0;
        st.hip_deep += solid.sdf(hip) < -2.0 ? 1 : 0;
        // The contact point: the proxy for the point tool; the ball's point on the constraint for a ball.
        const Vec3 cp = c.contact_point_m / kH;
        const double in_snap = snapshot_inside_cells(s, cp);
        const double in_exact = -solid.sdf(cp);
        st.worst_snapshot = std::max(st.worst_snapshot, in_snap);
        st.worst_analytic = std::max(st.worst_analytic, in_exact);
        if (in_snap > kSnapshotTol || in_exact > kAnalyticTol) {
            if (++st.failures <= 5)
                ADD_FAILURE() << solid.name << " r " << radius_cells << " mu " << mu << " seed " << seed << " tick " << t << ": contact point ("
                              << cp.x << ", " << cp.y << ", " << cp.z << ") cells is " << in_snap
                              << " cells inside by the rays, " << in_exact << " by the solid; hip (" << hip.x << ", "
                              << hip.y << ", " << hip.z << "), contact " << c.contact << " held " << c.held;
        }
    }
    return st;
}

TEST(ContactRandomWalk, ProxyNeverEndsInsideMaterial) {
    for (const Solid& solid : {sphere(), box_with_slot(), thin_plate()}) {
        const auto s = scan(solid);
        // Point tool, ball tool (radius 1.2 cells), point tool with Coulomb friction (mu_s 0.6, mu_d 0.42).
        for (const auto& [radius_cells, mu] : {std::pair{0.0, 0.0}, std::pair{1.2, 0.0}, std::pair{0.0, 0.6}}) {
            WalkStats all;
            for (unsigned seed = 1; seed <= 4; ++seed) {
                const WalkStats st = random_walk(solid, *s, radius_cells, mu, seed, 5000);
                all.ticks += st.ticks;
                all.contact += st.contact;
                all.held += st.held;
                all.hip_deep += st.hip_deep;
                all.failures += st.failures;
                all.worst_snapshot = std::max(all.worst_snapshot, st.worst_snapshot);
                all.worst_analytic = std::max(all.worst_analytic, st.worst_analytic);
            }
            std::printf("%-13s r %.1f cells, mu_s %.1f: %d ticks, %d in contact (%d held by the guard), HIP > 2 cells deep %d; "
                        "contact point at most %.3f cells inside by the rays, %.3f by the solid; %d failures\n",
                        solid.name.c_str(), radius_cells, mu, all.ticks, all.contact, all.held, all.hip_deep,
                        all.worst_snapshot, all.worst_analytic, all.failures);
            EXPECT_EQ(all.failures, 0) << solid.name;
            // The walks really did go deep into the material and touch it (else the test proves nothing).
            EXPECT_GT(all.contact, all.ticks / 20) << solid.name;
            if (solid.name != "thin plate") {
                EXPECT_GT(all.hip_deep, all.ticks / 20) << solid.name;
            }
        }
    }
}

}  // namespace
}  // namespace tridex::haptics
