// The subtracting tool's own recent sweeps taken as cut before the snapshot shows them (haptics/recent_cuts.hpp): the
// ray-capsule chord against a brute-force one, the interval cut, which sweeps a snapshot is missing, and a ball
// carving a groove back and forth at 1 kHz on a snapshot that lags the tool, whose proxy then stays with a HIP in
// free space.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "haptics/god_object.hpp"
#include "haptics/recent_cuts.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 d = b - a;
    const double dd = glm::dot(d, d);
    const double s = dd > 0.0 ? std::clamp(glm::dot(p - a, d) / dd, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + s * d));
}

TEST(RecentCuts, CapsuleChordMatchesBruteForce) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> c(-3.0, 3.0), rad(0.2, 2.5);
    int hits = 0;
    for (int n = 0; n < 600; ++n) {
        const int axis = n % 3;
        const Vec3 a(c(rng), c(rng), c(rng));
        const Vec3 b = n % 7 == 0 ? a : (n % 11 == 0 ? a + Vec3(axis == 0, axis == 1, axis == 2) * c(rng)
                                                     : Vec3(c(rng), c(rng), c(rng)));
        const double r = rad(rng), u = 0.5 * c(rng), v = 0.5 * c(rng);
        double t0 = 0.0, t1 = 0.0;
        const bool hit = ray_capsule_chord(axis, u, v, a, b, r, t0, t1);
        // Brute force: the ray's points within r of the segment, every 2e-4.
        double lo = 1e9, hi = -1e9;
        for (double t = -9.0; t <= 9.0; t += 2e-4) {
            Vec3 p(0.0);
            p[axis] = t;
            p[(axis + 1) % 3] = u;
            p[(axis + 2) % 3] = v;
            if (segment_distance(p, a, b) <= r) {
                lo = std::min(lo, t);
                hi = std::max(hi, t);
            }
        }
        if (lo > hi) {
            // A miss, or a graze thinner than the brute force's step.
            if (hit) {
                EXPECT_LT(t1 - t0, 0.05) << n;
            }
            continue;
        }
        ++hits;
        ASSERT_TRUE(hit) << n;
        EXPECT_NEAR(t0, lo, 3e-4) << n;
        EXPECT_NEAR(t1, hi, 3e-4) << n;
    }
    EXPECT_GT(hits, 150);
}

TEST(RecentCuts, CutRaySplitsTrimsAndKeepsTheNearest) {
    ActiveSurface s;
    ActiveSurface::Window& w = s.sets[2];
    constexpr int kK = ActiveSurface::kMaxIntervals;
    const auto set = [&](std::vector<std::pair<float, float>> iv, std::vector<int> mat) {
        w.count[0] = static_cast<std::uint8_t>(iv.size());
        for (std::size_t k = 0; k < iv.size(); ++k) {
            w.depth[k * 2] = iv[k].first;
            w.depth[k * 2 + 1] = iv[k].second;
            w.material[k] = static_cast<std::uint8_t>(mat[k]);
        }
        w.truncated = false;
    };
    set({{0.0f, 10.0f}}, {3});
    EXPECT_FALSE(cut_ray(w, 0, 0, 12.0, 14.0));  // misses
    EXPECT_FALSE(cut_ray(w, 0, 0, 5.0, 4.0));    // empty chord
    EXPECT_TRUE(cut_ray(w, 0, 0, 4.0, 6.0));     // splits
    ASSERT_EQ(w.intervals(0, 0), 2);
    EXPECT_EQ(w.enter(0, 0, 0), 0.0f);
    EXPECT_EQ(w.exit(0, 0, 0), 4.0f);
    EXPECT_EQ(w.enter(0, 0, 1), 6.0f);
    EXPECT_EQ(w.exit(0, 0, 1), 10.0f);
    EXPECT_EQ(w.material_of(0, 0, 1), 3);
    EXPECT_TRUE(cut_ray(w, 0, 0, -1.0, 7.0));  // takes the first, trims the second
    ASSERT_EQ(w.intervals(0, 0), 1);
    EXPECT_EQ(w.enter(0, 0, 0), 7.0f);
    EXPECT_TRUE(cut_ray(w, 0, 0, 0.0, 20.0));  // all gone
    EXPECT_EQ(w.intervals(0, 0), 0);
    // A full ray split once more keeps the kK pieces nearest the chord and says it was truncated.
    set({{0.0f, 1.0f}, {2.0f, 3.0f}, {4.0f, 5.0f}, {6.0f, 9.0f}}, {0, 1, 2, 4});
    EXPECT_TRUE(cut_ray(w, 0, 0, 7.0, 8.0));
    ASSERT_EQ(w.intervals(0, 0), kK);
    EXPECT_TRUE(w.truncated);
    EXPECT_EQ(w.enter(0, 0, 0), 2.0f);
    EXPECT_EQ(w.exit(0, 0, kK - 1), 9.0f);
    EXPECT_EQ(w.material_of(0, 0, kK - 1), 4);
}

// A slab z < 10 cells seen by its Z rays (the X and Y windows, around z = 32 cells, lie above it), cell 1 mm.
std::unique_ptr<ActiveSurface> slab(double applied_made_s) {
    auto s = test::published_surface(1e-3, 64, Vec3(32e-3), 0.0, [](int a, int, int) {
        return a == 2 ? test::Intervals{{0.0f, 10.0f}} : test::Intervals{};
    });
    s->sequence = 7;
    s->applied_made_s = applied_made_s;
    return s;
}

TEST(RecentCuts, SubtractsOnlyTheSweepsTheSnapshotLacks) {
    RecentCuts cuts;
    auto scratch = std::make_unique<ActiveSurface>();
    EXPECT_FALSE(cuts.add(Vec3(0.0), Vec3(std::nan("")), 1e-3, 1.0));
    EXPECT_FALSE(cuts.add(Vec3(0.0), Vec3(0.0), 0.0, 1.0));
    // Ball of 3 mm at (32, 32, 10) mm, made at t = 2 s; the slab's top under it sinks to 7 cells.
    ASSERT_TRUE(cuts.add(Vec3(32e-3, 32e-3, 10e-3), Vec3(32e-3, 32e-3, 10e-3), 3e-3, 2.0));
    const auto top_under = [](const ActiveSurface& s) {
        const auto w = s.to_window(2, Vec3(32e-3, 32e-3, 0.0));
        const int iu = static_cast<int>(std::lround(w.fu)), iv = static_cast<int>(std::lround(w.fv));
        const int n = s.sets[2].intervals(iu, iv);
        return n > 0 ? s.sets[2].exit(iu, iv, n - 1) : -1.0f;
    };
    auto held = slab(2.0);  // holds the sweep already
    EXPECT_EQ(&cuts.apply(*held, *scratch), held.get());
    auto unknown = slab(std::numeric_limits<double>::quiet_NaN());  // the publisher does not say: nothing predicted
    EXPECT_EQ(&cuts.apply(*unknown, *scratch), unknown.get());
    auto late = slab(1.0);  // made before the sweep
    const ActiveSurface& cut = cuts.apply(*late, *scratch);
    ASSERT_EQ(&cut, scratch.get());
    EXPECT_NEAR(top_under(cut), 7.0f, 1e-4);
    EXPECT_NEAR(top_under(*late), 10.0f, 1e-6);  // the snapshot itself is untouched
    // A later sweep on the same snapshot is added to the copy; a sample never applied before a snapshot with none
    // (-inf) is pending too.
    ASSERT_TRUE(cuts.add(Vec3(32e-3, 32e-3, 10e-3), Vec3(32e-3, 32e-3, 9e-3), 3e-3, 3.0));
    EXPECT_NEAR(top_under(cuts.apply(*late, *scratch)), 6.0f, 1e-4);
    auto first = slab(-std::numeric_limits<double>::infinity());
    first->sequence = 8;
    EXPECT_NEAR(top_under(cuts.apply(*first, *scratch)), 6.0f, 1e-4);
    // Sweeps recorded from samples: only a pushed subtracting ball after an earlier pushed sample.
    RecentCuts from_samples;
    ToolSample s;
    s.tool.kind = ToolKind::kBall;
    s.tool.radius_m = 3e-3;
    s.op = ToolOp::kSubtract;
    s.made_s = 1.0;
    EXPECT_FALSE(from_samples.note(s, true));   // the first: no sweep yet
    s.made_s = 2.0;
    EXPECT_FALSE(from_samples.note(s, false));  // not pushed
    s.made_s = 3.0;
    EXPECT_TRUE(from_samples.note(s, true));
    for (ToolOp op : {ToolOp::kNone, ToolOp::kUnion, ToolOp::kPaint, ToolOp::kPush, ToolOp::kSmooth, ToolOp::kPull}) {
        s.op = op;
        s.made_s += 1.0;
        EXPECT_FALSE(from_samples.note(s, true)) << tool_op_name(op);
    }
    EXPECT_EQ(from_samples.size(), 1);
    cuts.clear();
    EXPECT_EQ(&cuts.apply(*late, *scratch), late.get());
}

// A ball carving a groove into a slab at 1 kHz, its centre 1.1 radii into the slab, 0.75 m/s along x and back twice,
// on a snapshot published every 4 ticks that shows the sweeps of samples at least `latency` ticks old (as the sculpt
// thread's, which applies what it drained, then publishes). Returns the ticks with the HIP outside the solid by more
// than a hundredth of a cell and the proxy more than one radius (+ a hundredth of a cell) from it, and sets the
// largest such gap (m). `predict`: the contact reads the snapshot with the loop's own later sweeps cut (RecentCuts).
int carve_back_and_forth(int latency, bool predict, double& worst_gap_m) {
    constexpr double kCell = 1e-3, kR = 6e-3, kTop = 50e-3;
    constexpr int kNodes = 128;
    ContactParams params;
    params.tool_radius_m = kR;
    GodObject god(params);
    RecentCuts cuts;
    auto scratch = std::make_unique<ActiveSurface>();
    std::unique_ptr<ActiveSurface> snapshot;
    std::vector<Vec3> hips;  // the sample of tick k is hips[k]; its sweep runs from hips[k - 1]
    // Solid intervals of a ray: the slab's, less the sweeps of samples 1..upto.
    const auto rays = [&](int upto) {
        return [&, upto](int a, int u, int v) {
            Vec3 p(0.0);
            p[(a + 1) % 3] = u;
            p[(a + 2) % 3] = v;
            test::Intervals iv;
            if (a == 2) iv = {{0.0f, static_cast<float>(kTop / kCell)}};
            else if (p.z * kCell < kTop) iv = {{0.0f, static_cast<float>(kNodes - 1)}};
            for (int k = 1; k <= upto; ++k) {
                const Vec3 ga = hips[k - 1] / kCell, gb = hips[k] / kCell;
                double t0 = 0.0, t1 = 0.0;
                if (!ray_capsule_chord(a, u, v, ga, gb, kR / kCell, t0, t1)) continue;
                test::Intervals out;
                for (const auto& [e, x] : iv) {
                    if (t1 <= e || t0 >= x) {
                        out.push_back({e, x});
                        continue;
                    }
                    if (t0 > e) out.push_back({e, static_cast<float>(t0)});
                    if (t1 < x) out.push_back({static_cast<float>(t1), x});
                }
                iv = out;
            }
            return iv;
        };
    };
    const auto outside_by = [&](const Vec3& p, int upto) {  // signed distance from the solid (m), > 0 outside
        double d = p.z - kTop;
        for (int k = 1; k <= upto; ++k) d = std::max(d, kR - segment_distance(p, hips[k - 1], hips[k]));
        return d;
    };
    // The path: down from above the slab to 1.1 radii in, then 30 mm along x and back, twice.
    std::vector<Vec3> path;
    const Vec3 start(49e-3, 64e-3, kTop + kR + 2e-3), pressed(49e-3, 64e-3, kTop - 0.1 * kR);
    for (int t = 0; t <= 40; ++t) path.push_back(start + (pressed - start) * (t / 40.0));
    for (int leg = 0; leg < 4; ++leg)
        for (int t = 1; t <= 40; ++t) path.push_back(pressed + Vec3((leg % 2 == 0 ? t : 40 - t) * 0.75e-3, 0.0, 0.0));
    for (int t = 0; t < 60; ++t) path.push_back(path.back());
    int over = 0;
    worst_gap_m = 0.0;
    for (std::size_t n = 0; n < path.size(); ++n) {
        const int applied = static_cast<int>(n) - 1 - latency;  // newest sample the snapshot may hold
        if (!snapshot || n % 4 == 0) {
            const int upto = std::max(0, applied);
            snapshot = test::published_surface(kCell, kNodes, hips.empty() ? path[0] : hips[upto], kR + 3e-3,
                                               rays(upto));
            snapshot->sequence = n + 1;
            snapshot->applied_made_s = applied >= 0 ? static_cast<double>(applied) : -1.0;
        }
        const Vec3 hip = path[n];
        const ActiveSurface& read = predict ? cuts.apply(*snapshot, *scratch) : *snapshot;
        const ContactResult c = god.update(read, hip, 1e-3);
        const double gap = glm::length(c.proxy_m - hip);
        if (outside_by(hip, static_cast<int>(n) - 1) > 0.01 * kCell && gap > kR + 0.01 * kCell) {
            ++over;
            worst_gap_m = std::max(worst_gap_m, gap);
        }
        // The sample this tick pushes; the sculpt thread sweeps it from the one before.
        if (!hips.empty()) cuts.add(hips.back(), hip, kR, static_cast<double>(n));
        hips.push_back(hip);
    }
    return over;
}

TEST(RecentCuts, ProxyFollowsAHipInItsOwnFreshGroove) {
    for (const int latency : {0, 10, 30, 60}) {
        double gap_stale = 0.0, gap_predicted = 0.0;
        const int stale = carve_back_and_forth(latency, false, gap_stale);
        const int predicted = carve_back_and_forth(latency, true, gap_predicted);
        std::printf("[recent cuts] snapshot %d ticks late: ticks over one radius with the HIP outside %d (worst gap "
                    "%.2f mm) without the tool's own sweeps, %d (%.2f mm) with them\n",
                    latency, stale, 1e3 * gap_stale, predicted, 1e3 * gap_predicted);
        EXPECT_EQ(predicted, 0) << latency;
        if (latency >= 10) {
            EXPECT_GT(stale, 0) << latency;  // the fault this guards against shows without them
        }
    }
}

}  // namespace
}  // namespace tridex::haptics
