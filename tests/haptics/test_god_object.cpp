// Tests of haptics/god_object: planes (point and ball tool), slopes on Z and X rays, enter ends, free
// space, a thin slab, oblique approach, a convex edge, the active triangle following the HIP, and the
// update time.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/error.hpp"
#include "haptics/god_object.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

using test::fill_set;
using test::Intervals;
using test::make_surface;
using test::z_plane;

constexpr double kH = 1e-3;         // cell, m
constexpr float kC = 10.25f;        // plane height, cells (exact in float)
constexpr double kKp = 700.0;       // N/m
constexpr double kDt = 1e-3;        // s
constexpr double kTolM = 1e-12;     // m: double rounding on positions ~0.03 m
constexpr double kTolN = 1e-9;      // N

Vec3 mm(double x, double y, double z) { return Vec3(x, y, z) * 1e-3; }

void expect_vec(const Vec3& a, const Vec3& b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

TEST(GodObject, PointToolBelowPlanePushesUpByStiffness) {
    const auto s = z_plane(kH, kC);
    GodObject g(ContactParams{kKp, 0.0, 0.0});
    const ContactResult free = g.update(*s, mm(10.3, 12.7, 12.0), kDt);
    EXPECT_FALSE(free.contact);
    const ContactResult c = g.update(*s, mm(10.3, 12.7, 8.25), kDt);  // 2 mm below the plane
    ASSERT_TRUE(c.contact);
    EXPECT_EQ(c.axis, 2);
    EXPECT_NEAR(c.depth_m, 2e-3, kTolM);
    expect_vec(c.normal, Vec3(0, 0, 1), 0.0);
    expect_vec(c.force_n, Vec3(0, 0, kKp * 2e-3), kTolN);
    expect_vec(c.proxy_m, mm(10.3, 12.7, 10.25), kTolM);  // on the plane, above the HIP
    // Sliding sideways at the same depth keeps the same force; the proxy follows on the plane.
    const ContactResult d = g.update(*s, mm(17.9, 3.1, 8.25), kDt);
    ASSERT_TRUE(d.contact);
    expect_vec(d.force_n, Vec3(0, 0, 1.4), kTolN);
    expect_vec(d.proxy_m, mm(17.9, 3.1, 10.25), kTolM);
}

TEST(GodObject, BallToolRestsOnPlane) {
    const auto s = z_plane(kH, kC);
    const double r = 3e-3;
    GodObject g(ContactParams{kKp, 0.0, r});
    EXPECT_FALSE(g.update(*s, mm(5.5, 5.5, 14.0), kDt).contact);  // lowest point 0.75 mm above the plane
    const ContactResult c = g.update(*s, mm(5.5, 5.5, 11.25), kDt); // centre 1 mm above: depth r - 1 mm
    ASSERT_TRUE(c.contact);
    EXPECT_NEAR(c.depth_m, 2e-3, kTolM);
    expect_vec(c.force_n, Vec3(0, 0, 1.4), kTolN);
    expect_vec(c.proxy_m, mm(5.5, 5.5, 10.25 + 3.0), kTolM);  // the ball's centre resting on the plane
    // Deeper than the radius: HIP 2 mm below the plane, depth 5 mm.
    const ContactResult d = g.update(*s, mm(5.5, 5.5, 8.25), kDt);
    ASSERT_TRUE(d.contact);
    EXPECT_NEAR(d.depth_m, 5e-3, kTolM);
    expect_vec(d.proxy_m, mm(5.5, 5.5, 13.25), kTolM);
}

TEST(GodObject, DampingActsOnPenetrationRateAndNeverPulls) {
    const auto s = z_plane(kH, kC);
    GodObject g(ContactParams{kKp, 2.0, 0.0});
    g.update(*s, mm(10, 10, 11), kDt);
    // First contact tick: depth 2 mm reached in 1 ms -> rate 2 m/s, F = 700*0.002 + 2*2 = 5.4 N.
    expect_vec(g.update(*s, mm(10, 10, 8.25), kDt).force_n, Vec3(0, 0, 5.4), kTolN);
    // Held still: rate 0 -> the spring alone.
    expect_vec(g.update(*s, mm(10, 10, 8.25), kDt).force_n, Vec3(0, 0, 1.4), kTolN);
    // Withdrawing 1 mm in 1 ms: 0.7 - 2 < 0 -> clamped to zero (still in contact), never pulling.
    const ContactResult w = g.update(*s, mm(10, 10, 9.25), kDt);
    EXPECT_TRUE(w.contact);
    expect_vec(w.force_n, Vec3(0.0), 0.0);
    // dt <= 0 drops the damping term.
    expect_vec(g.update(*s, mm(10, 10, 8.25), 0.0).force_n, Vec3(0, 0, 1.4), kTolN);
}

// z = c + sx * x + sy * y (grid units), solid below, seen by Z rays.
TEST(GodObject, SlopedPlaneOnZRaysGivesItsNormal) {
    const double sx = 0.3, sy = -0.2;
    auto s = make_surface(kH);
    fill_set(*s, 2, 0, 0, [&](int i, int j) { return Intervals{{0.0f, static_cast<float>(kC + sx * i + sy * j)}}; });
    const Vec3 n_exact = glm::normalize(Vec3(-sx, -sy, 1.0));
    // Two HIPs: one in each half of a cell (fractional x > y and x < y).
    for (const Vec3& xy : {Vec3(12.7, 9.2, 0.0), Vec3(12.2, 9.7, 0.0)}) {
        GodObject g(ContactParams{kKp, 0.0, 0.0});
        const double surface_z = kC + sx * xy.x + sy * xy.y;  // cells
        g.update(*s, mm(xy.x, xy.y, surface_z + 1.0), kDt);
        const ContactResult c = g.update(*s, mm(xy.x, xy.y, surface_z - 1.5), kDt);
        ASSERT_TRUE(c.contact);
        // Depths are floats ~14 cells: rounding 1e-6 cells -> normal within 5e-6, depth within 5e-9 m.
        expect_vec(c.normal, n_exact, 5e-6);
        EXPECT_NEAR(c.depth_m, 1.5e-3 * n_exact.z, 5e-9);  // vertical 1.5 mm times cos(slope)
        expect_vec(c.force_n, kKp * c.depth_m * c.normal, kTolN);
        // The proxy lies on the plane.
        EXPECT_NEAR(glm::dot(c.proxy_m - mm(0, 0, kC), n_exact), 0.0, 5e-9);
    }
}

// x = c + s * y (grid units), solid at smaller x, seen by X rays (u = y, v = z); approach along -x.
TEST(GodObject, SlopedPlaneOnXRaysGivesItsNormal) {
    const double sl = 0.4;
    auto s = make_surface(kH);
    fill_set(*s, 0, 0, 0, [&](int u, int) { return Intervals{{0.0f, static_cast<float>(kC + sl * u)}}; });
    const Vec3 n_exact = glm::normalize(Vec3(1.0, -sl, 0.0));
    GodObject g(ContactParams{kKp, 0.0, 0.0});
    const double y = 7.4, z = 20.6, surface_x = kC + sl * y;
    g.update(*s, mm(surface_x + 2.0, y, z), kDt);
    const ContactResult c = g.update(*s, mm(surface_x - 1.0, y, z), kDt);
    ASSERT_TRUE(c.contact);
    EXPECT_EQ(c.axis, 0);
    expect_vec(c.normal, n_exact, 5e-6);
    EXPECT_NEAR(c.depth_m, 1e-3 * n_exact.x, 5e-9);
}

TEST(GodObject, EnterEndsFaceTheOtherWay) {
    // Solid above z = c: approaching from below, the surface is the rays' enter end, normal -z.
    auto s = make_surface(kH);
    fill_set(*s, 2, 0, 0, [](int, int) { return Intervals{{kC, 60.0f}}; });
    GodObject g(ContactParams{kKp, 0.0, 0.0});
    g.update(*s, mm(8, 8, 9), kDt);
    const ContactResult c = g.update(*s, mm(8, 8, 11.25), kDt);
    ASSERT_TRUE(c.contact);
    expect_vec(c.normal, Vec3(0, 0, -1), 0.0);
    expect_vec(c.force_n, Vec3(0, 0, -0.7), kTolN);
    expect_vec(c.proxy_m, mm(8, 8, 10.25), kTolM);
}

void expect_free(const ContactResult& c, const Vec3& hip) {
    EXPECT_FALSE(c.contact);
    EXPECT_EQ(c.force_n, Vec3(0.0));
    EXPECT_EQ(c.proxy_m, hip);
    EXPECT_EQ(c.axis, -1);
}

TEST(GodObject, NoForceInFreeSpaceOrWithoutData) {
    auto s = z_plane(kH, kC);
    GodObject g(ContactParams{kKp, 1.0, 0.0});
    expect_free(g.update(*s, mm(10, 10, 12), kDt), mm(10, 10, 12));  // above the plane
    expect_free(g.update(*s, mm(10, 10, 10.3), kDt), mm(10, 10, 10.3));
    // Outside the window (x beyond lattice node 31): no data, no force.
    g.reset();
    g.update(*s, mm(40, 10, 12), kDt);
    expect_free(g.update(*s, mm(40, 10, 8), kDt), mm(40, 10, 8));
    // A hole: one ray of the triangle is empty.
    auto holed = z_plane(kH, kC);
    holed->sets[2].count[10 + ActiveSurface::kWindow * 10] = 0;
    g.reset();
    g.update(*holed, mm(10.5, 10.2, 12), kDt);
    expect_free(g.update(*holed, mm(10.5, 10.2, 8), kDt), mm(10.5, 10.2, 8));
    // Nothing published yet (sequence 0).
    auto unpublished = z_plane(kH, kC);
    unpublished->sequence = 0;
    g.reset();
    g.update(*unpublished, mm(10, 10, 12), kDt);
    expect_free(g.update(*unpublished, mm(10, 10, 8), kDt), mm(10, 10, 8));
    // A NaN HIP.
    EXPECT_FALSE(g.update(*s, Vec3(std::nan("")), kDt).contact);
}

// A slab 0.5 cell thick (0.5 mm) with its top at c; the HIP goes down to 3 mm below the top. While the tool
// overlaps the slab or lies within a cell under it, the god-object rests on the top (no pop-through); once the
// tool is clear of the far side by more than a cell, the proxy joins the HIP (it is never left behind).
TEST(GodObject, ThinSlabHoldsUntilTheToolIsClearOfItsFarSide) {
    auto s = make_surface(kH);
    fill_set(*s, 2, 0, 0, [](int, int) { return Intervals{{kC - 0.5f, kC}}; });
    for (double r : {0.0, 1e-3}) {
        GodObject g(ContactParams{kKp, 0.0, r});
        int held = 0, released = 0;
        for (int k = 0; k <= 40; ++k) {
            const double z = 11.25 + r * 1e3 - 0.1 * k;  // from 1 mm above contact, 0.1 mm per tick
            const ContactResult c = g.update(*s, mm(9.3, 9.6, z), kDt);
            const double depth = r + (10.25 - z) * 1e-3;
            if (depth <= 1e-9) continue;  // not touching yet
            if (z > 8.8) {  // the tool overlaps the slab, or is within a cell under its bottom (9.75 mm)
                ASSERT_TRUE(c.contact) << "r " << r << " z " << z;
                EXPECT_NEAR(c.proxy_m.z, 10.25e-3 + r, kTolM);
                expect_vec(c.force_n, Vec3(0, 0, kKp * depth), kTolN);
                ++held;
            } else if (z < 8.7) {  // clear of the far side by more than a cell
                EXPECT_FALSE(c.contact) << "r " << r << " z " << z;
                expect_vec(c.proxy_m, mm(9.3, 9.6, z), 0.0);
                expect_vec(c.force_n, Vec3(0.0), 0.0);
                ++released;
            }
        }
        EXPECT_GT(held, 5);
        EXPECT_GE(released, 5);
    }
    // In one tick from 1 mm above to 0.75 mm under the top (inside the cell under the bottom): held on the top.
    GodObject g(ContactParams{kKp, 0.0, 0.0});
    g.update(*s, mm(9.3, 9.6, 11.25), kDt);
    const ContactResult c = g.update(*s, mm(9.3, 9.6, 9.5), kDt);
    ASSERT_TRUE(c.contact);
    expect_vec(c.force_n, Vec3(0, 0, kKp * 0.75e-3), kTolN);
    // In one tick to 3 mm under the top: the hand went through, the proxy is with it.
    const ContactResult through = g.update(*s, mm(9.3, 9.6, 7.25), kDt);
    EXPECT_FALSE(through.contact);
    expect_vec(through.proxy_m, mm(9.3, 9.6, 7.25), 0.0);
    // Coming back up to well above the top in one tick: free again (just above it, the slab would hold it from below).
    EXPECT_FALSE(g.update(*s, mm(9.3, 9.6, 11.5), kDt).contact);
}

// Mouse-like input at 1 kHz: random jumps of up to 12 mm per tick and fast sweeps through a slab 0.5 cell
// thick, for a point and a 1.5 mm ball. Whenever the tool is clear of the slab by more than a cell and a
// tolerance (exact: the slab is infinite in the window), the proxy is on the HIP and there is no force; in
// contact, the proxy is never inside the slab.
TEST(GodObject, ProxyIsNeverLeftBehindAFreeToolOnJumpsAndSweeps) {
    auto s = make_surface(kH);
    fill_set(*s, 2, 0, 0, [](int, int) { return Intervals{{kC - 0.5f, kC}}; });
    const double top = kC * kH, bottom = (kC - 0.5) * kH;
    std::uint64_t state = 12345;
    auto uniform = [&state](double lo, double hi) {  // a fixed LCG: the same walk on every machine
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return lo + (hi - lo) * static_cast<double>(state >> 11) / 9007199254740992.0;
    };
    for (double r : {0.0, 1.5e-3}) {
        GodObject g(ContactParams{kKp, 0.5, r});
        double worst_free_m = 0.0, deepest_proxy_m = 0.0;
        int free_ticks = 0, contact_ticks = 0;
        Vec3 hip = mm(16, 16, 14);
        for (int t = 0; t < 20000; ++t) {
            if (t % 200 < 100) {
                hip = mm(uniform(6, 26), uniform(6, 26), uniform(4, 16));  // jumps anywhere
            } else {  // sweeps down and up through the slab, 1.2 mm per tick
                const double phase = (t % 100) / 50.0;
                hip = mm(10 + 0.05 * (t % 100), 16, phase < 1.0 ? 16 - 12 * phase : 4 + 12 * (phase - 1.0));
            }
            const ContactResult c = g.update(*s, hip, kDt);
            const double margin = kH + 1e-9;
            const bool clear = hip.z - r > top + margin || hip.z + r < bottom - margin;
            if (clear) {
                ++free_ticks;
                worst_free_m = std::max(worst_free_m, glm::length(c.proxy_m - hip));
                EXPECT_FALSE(c.contact) << "tick " << t;
                EXPECT_EQ(c.force_n, Vec3(0.0)) << "tick " << t;
            }
            if (c.contact) {
                ++contact_ticks;
                const double pz = c.proxy_m.z;  // the ball's centre: its surface is r from it
                if (pz - r < top && pz + r > bottom)
                    deepest_proxy_m = std::max(deepest_proxy_m, std::min(top - (pz - r), (pz + r) - bottom));
            }
        }
        std::printf("[ proxy    ] r %.1f mm: %d free ticks, largest proxy-to-HIP distance %.3g m; %d contact ticks, "
                    "proxy at most %.3g m inside the slab\n",
                    r * 1e3, free_ticks, worst_free_m, contact_ticks, deepest_proxy_m);
        EXPECT_GT(free_ticks, 5000);
        EXPECT_GT(contact_ticks, 500);
        EXPECT_EQ(worst_free_m, 0.0);
        EXPECT_LE(deepest_proxy_m, 0.25 * kH + 1e-9);  // the guard's quarter cell
    }
}

TEST(GodObject, StartingInsideMaterialFeelsNothing) {
    const auto s = z_plane(kH, kC);
    GodObject g(ContactParams{kKp, 0.0, 0.0});
    EXPECT_FALSE(g.update(*s, mm(10, 10, 8), kDt).contact);  // no plane was crossed
    EXPECT_FALSE(g.update(*s, mm(10, 10, 7), kDt).contact);
    EXPECT_FALSE(g.update(*s, mm(10, 10, 12), kDt).contact);  // out
    EXPECT_TRUE(g.update(*s, mm(10, 10, 9), kDt).contact);    // and in again: now it is felt
}

// The half-space z < c as all three ray sets see it (X and Y rays fully solid on nodes below c).
std::unique_ptr<ActiveSurface> half_space_all_sets() {
    auto s = z_plane(kH, kC);
    fill_set(*s, 0, 0, 0, [](int, int z) { return z < kC ? Intervals{{0.0f, 63.0f}} : Intervals{}; });
    fill_set(*s, 1, 0, 0, [](int z, int) { return z < kC ? Intervals{{0.0f, 63.0f}} : Intervals{}; });
    return s;
}

TEST(GodObject, ObliqueApproachFindsTheCrossedFace) {
    const auto s = half_space_all_sets();
    // Mostly along +x and a little down: the X rays are tried first. Straddling the surface they have an
    // empty ray; one cell deeper they are all solid, but their nearest end (x = 0) is a face the proxy
    // was already 10 mm behind. Either way the Z rays give the top face.
    for (double z_end : {10.05, 9.5}) {
        GodObject g(ContactParams{kKp, 0.0, 0.0});
        g.update(*s, mm(10.0, 10.0, 10.6), kDt);
        const ContactResult c = g.update(*s, mm(11.1, 10.0, z_end), kDt);
        ASSERT_TRUE(c.contact) << z_end;
        EXPECT_EQ(c.axis, 2);
        expect_vec(c.normal, Vec3(0, 0, 1), 0.0);
        EXPECT_NEAR(c.depth_m, (10.25 - z_end) * 1e-3, kTolM);
    }
}

TEST(GodObject, SlidingOffAConvexEdgeReleases) {
    // A block x <= 20, z <= c (cells) in all three ray sets.
    auto s = make_surface(kH);
    fill_set(*s, 2, 0, 0, [](int x, int) { return x <= 20 ? Intervals{{0.0f, kC}} : Intervals{}; });
    fill_set(*s, 0, 0, 0, [](int, int z) { return z < kC ? Intervals{{0.0f, 20.0f}} : Intervals{}; });
    fill_set(*s, 1, 0, 0, [](int z, int x) { return z < kC && x <= 20 ? Intervals{{0.0f, 63.0f}} : Intervals{}; });
    GodObject g(ContactParams{kKp, 0.0, 0.0});
    g.update(*s, mm(15, 10, 11), kDt);
    for (double x = 15.0; x <= 19.5; x += 0.5) {
        const ContactResult c = g.update(*s, mm(x, 10, 9.75), kDt);
        ASSERT_TRUE(c.contact) << x;
        expect_vec(c.normal, Vec3(0, 0, 1), 0.0);
    }
    // Past the edge the HIP is outside the block: released, not pushed sideways by the side face.
    for (double x = 20.5; x <= 22.0; x += 0.5) expect_free(g.update(*s, mm(x, 10, 9.75), kDt), mm(x, 10, 9.75));
}

// The active triangle follows the HIP: each tick its three dexel points are the rays of the half cell
// under the HIP's projection, and it changes exactly when the HIP leaves that half cell's cover.
TEST(GodObject, NewTriangleWhenTheHipLeavesItsCover) {
    const double sx = 0.3, sy = -0.2;
    auto s = make_surface(kH);
    fill_set(*s, 2, 0, 0, [&](int i, int j) { return Intervals{{0.0f, static_cast<float>(kC + sx * i + sy * j)}}; });
    GodObject g(ContactParams{kKp, 0.0, 0.0});
    const Vec3 a(3.3, 5.1, 0.0), b(12.7, 9.4, 0.0);  // cells
    g.update(*s, mm(a.x, a.y, kC + sx * a.x + sy * a.y + 0.5), kDt);
    int changes = 0, cover_changes = 0, last_key = -1;
    std::array<Vec3, 3> last{};
    for (int k = 0; k <= 400; ++k) {
        const Vec3 p = a + (b - a) * (k / 400.0);
        const ContactResult c = g.update(*s, mm(p.x, p.y, kC + sx * p.x + sy * p.y - 1.0), kDt);
        ASSERT_TRUE(c.contact) << k;
        const int iu = static_cast<int>(p.x), iv = static_cast<int>(p.y);
        const bool lower = p.x - iu >= p.y - iv;
        const int key = (iu * 64 + iv) * 2 + (lower ? 1 : 0);
        const Vec3 expect[3] = {Vec3(iu, iv, 0), Vec3(iu + 1, lower ? iv : iv + 1, 0), Vec3(lower ? iu + 1 : iu, iv + 1, 0)};
        for (int v = 0; v < 3; ++v) {
            EXPECT_NEAR(c.triangle_m[v].x, expect[v].x * kH, kTolM) << k;
            EXPECT_NEAR(c.triangle_m[v].y, expect[v].y * kH, kTolM) << k;
            // The dexel point is the ray's end: on the plane.
            EXPECT_NEAR(c.triangle_m[v].z, (kC + sx * expect[v].x + sy * expect[v].y) * kH, 1e-8) << k;
        }
        if (k > 0) {
            cover_changes += key != last_key ? 1 : 0;
            changes += c.triangle_m != last ? 1 : 0;
        }
        last_key = key;
        last = c.triangle_m;
    }
    EXPECT_EQ(changes, cover_changes);
    EXPECT_GT(cover_changes, 15);  // the line crosses 9 columns, 4 rows and about 13 diagonals
}

TEST(GodObject, RejectsBadParameters) {
    EXPECT_THROW(GodObject(ContactParams{-1.0, 0.0, 0.0}), Error);
    EXPECT_THROW(GodObject(ContactParams{700.0, std::nan(""), 0.0}), Error);
    EXPECT_THROW(GodObject(ContactParams{700.0, 0.0, -1e-3}), Error);
}

// A HIP circling in and out of contact: every update's force is finite and bounded, and the circle touches the
// surface part of the time. The update's time is printed for reading, not checked: timings belong to
// `tridex bench --haptics` (a shared machine makes any bound here flaky).
TEST(GodObject, CirclingInAndOutOfContactStaysBounded) {
    const auto s = half_space_all_sets();
    for (const double r : {2e-3, 0.0}) {
        GodObject g(ContactParams{kKp, 0.5, r});
        constexpr int kCalls = 100000;
        std::vector<double> ns(kCalls);
        double sink = 0.0, largest_n = 0.0;
        for (int i = 0; i < kCalls; ++i) {
            // A HIP circling in and out of contact over the surface (2 mm radius, 1 mm deep on average).
            const double a = 1e-3 * i;
            const Vec3 hip = mm(15.0 + 2.0 * std::cos(a), 15.0 + 2.0 * std::sin(a), 11.25 + 1.5 * std::sin(7.0 * a));
            const auto t0 = std::chrono::steady_clock::now();
            const ContactResult c = g.update(*s, hip, kDt);
            const auto t1 = std::chrono::steady_clock::now();
            ASSERT_TRUE(std::isfinite(c.force_n.x) && std::isfinite(c.force_n.y) && std::isfinite(c.force_n.z)) << i;
            sink += c.force_n.z;
            largest_n = std::max(largest_n, glm::length(c.force_n));
            ns[i] = static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count());
        }
        std::sort(ns.begin(), ns.end());
        std::printf("god-object update, tool radius %.0f mm: median %.3f us, p99 %.3f us over %d calls (force sum %.3g N)\n",
                    r * 1e3, ns[kCalls / 2] * 1e-3, ns[kCalls * 99 / 100] * 1e-3, kCalls, sink);
        EXPECT_GT(sink, 0.0);  // the circle really was in contact part of the time
        // The HIP is at most 2.75 mm below the surface: the spring force stays within kKp times that (and damping).
        EXPECT_LT(largest_n, kKp * 2.75e-3 + 1.0);
    }
}

}  // namespace
}  // namespace tridex::haptics
