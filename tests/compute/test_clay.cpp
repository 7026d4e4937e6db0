// Tests of the clay tools (push, smooth, pull) on the CPU reference: Popescu's dent and the rim on a plane, pull as
// push's inverse, volume over strokes, three-set agreement, smoothing a noisy sphere, a plane left alone, undo restoring exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "clay_test_models.hpp"
#include "compute/history/undo_history.hpp"
#include "compute/tools/clay_push.hpp"
#include "compute/tools/clay_smooth.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "core/error.hpp"

namespace tridex::compute {
namespace {

using clay_test::clay_sweep;
using clay_test::cube_lattice;
using clay_test::from_implicit;
using clay_test::slab;
using clay_test::volume_cells;

constexpr double kCell = 1e-3;  // cube_lattice: 1 mm cells from the origin, so grid units = mm

/// Top crossing (cells) of the Z ray at node (i, j): the exit of its last interval.
float top_of(const TriDexel& m, int i, int j) {
    const auto& ray = m.sets[2].ray(i, j);
    return ray.empty() ? -1.0f : ray.back().exit;
}

TEST(ClayPush, PlaneGivesPopescusDentAndAVolumeKeepingRim) {
    const double z0 = 20.3;
    TriDexel m = from_implicit(cube_lattice(48), slab(z0));
    const double v0 = volume_cells(m);
    const std::size_t disagree0 = clay_set_disagreement(m, clay_whole_box(m.lattice));
    const double R = 4.0, delta = 0.8, r = kClayInfluence * R, w = kClayRimWidth * r;
    const Vec3 c(24.2, 24.3, z0 + R - delta);
    const ClayStats st = apply_clay(m, clay_sweep(ToolOp::kPush, c, c, R));
    EXPECT_GT(st.rays.rays_changed, 0u);
    double rim_max = 0.0, worst = 0.0;
    for (int j = 0; j <= 48; ++j)
        for (int i = 0; i <= 48; ++i) {
            const double rho = std::hypot(i - c.x, j - c.y);
            const double top = top_of(m, i, j);
            if (rho < r) {  // Popescu 3.3: displacement delta * (1 - (d/r)^2)
                const double expect = z0 - delta * (1.0 - (rho / r) * (rho / r));
                worst = std::max(worst, std::fabs(top - expect));
                EXPECT_NEAR(top, expect, 0.5) << i << "," << j;
            } else if (rho < r + w) {
                EXPECT_GE(top, z0 - 1e-3) << i << "," << j;  // the rim only rises
                rim_max = std::max(rim_max, top - z0);
            } else if (rho > r + w + 1.0 && i > 4 && i < 44 && j > 4 && j < 44) {
                EXPECT_EQ(top, static_cast<float>(z0)) << i << "," << j;  // untouched beyond the rim, bit for bit
            }
        }
    EXPECT_GT(rim_max, 0.02);
    const double dent = M_PI * delta * r * r / 2.0;  // analytic dent volume on a plane, cells^3
    const double dv = volume_cells(m) - v0;
    std::printf(
        "plane push: dent %.2f cells^3, net volume change %.4f cells^3 (%.3f%% of the dent), rim %.3f cells, "
        "profile error %.3f cells, beta %.3f, set disagreement %zu -> %zu nodes\n",
        dent, dv, 100.0 * dv / dent, rim_max, worst, st.beta, disagree0,
        clay_set_disagreement(m, clay_whole_box(m.lattice)));
    // One sub-cell push on a lattice-aligned face: the X and Y sets sample this surface at whole nodes, so the model's
    // volume (the mean of the three sets) moves in steps of a node layer under the dent and one operation cannot
    // balance it finely; relative to the model it is far inside 2%, and over a stroke the steps average out
    // (StrokeKeepsVolumeAndTheSetsAgree: 0.001%).
    EXPECT_LT(std::fabs(dv), 0.02 * v0);
    EXPECT_LT(std::fabs(dv), 1.0 * dent);
    EXPECT_LE(clay_set_disagreement(m, clay_whole_box(m.lattice)), disagree0 + 2);
}

TEST(ClayPush, NoContactNoChange) {
    const double z0 = 20.3;
    TriDexel m = from_implicit(cube_lattice(48), slab(z0));
    const Vec3 c(24.0, 24.0, z0 + 4.0 + 0.5);  // half a cell above the surface
    const ClayStats st = apply_clay(m, clay_sweep(ToolOp::kPush, c, c + Vec3(1.0, 0.0, 0.0), 4.0));
    EXPECT_EQ(st.rays.rays_changed, 0u);
    // A tool larger than the field's search distance: no contact 2 cells above, a dent 0.5 cell in.
    const Vec3 far(24.0, 24.0, z0 + 9.0 + 2.0);
    EXPECT_EQ(apply_clay(m, clay_sweep(ToolOp::kPush, far, far, 9.0)).rays.rays_changed, 0u);
    const Vec3 in(24.0, 24.0, z0 + 9.0 - 0.5);
    EXPECT_GT(apply_clay(m, clay_sweep(ToolOp::kPush, in, in, 9.0)).rays.rays_changed, 0u);
    EXPECT_NEAR(top_of(m, 24, 24), z0 - 0.5, 0.1);
}

TEST(ClayPush, StrokeKeepsVolumeAndTheSetsAgree) {
    const double ctr[3] = {24.0, 24.0, 24.0}, rho = 14.0;
    TriDexel m = from_implicit(cube_lattice(48), [&](double x, double y, double z) {
        return std::sqrt((x - ctr[0]) * (x - ctr[0]) + (y - ctr[1]) * (y - ctr[1]) + (z - ctr[2]) * (z - ctr[2])) - rho;
    });
    const double v0 = volume_cells(m);
    const std::size_t disagree0 = clay_set_disagreement(m, clay_whole_box(m.lattice));
    // Press in from the top, then slide across, 0.05 cell per segment (a 1 kHz hand at 50 mm/s on 1 mm cells).
    const double R = 3.0;
    Vec3 p(24.0, 24.0, 24.0 + rho + R + 0.5);
    double dent = 0.0;
    std::size_t segments = 0;
    auto go = [&](const Vec3& to) {
        const int n = static_cast<int>(std::ceil(glm::length(to - p) / 0.05));
        for (int k = 1; k <= n; ++k) {
            const Vec3 q = p + (to - p) * (static_cast<double>(k) / n);
            const ClayStats st = apply_clay(m, clay_sweep(ToolOp::kPush, p, q, R));
            dent += st.max_displacement_cells;
            p = q;
            ++segments;
        }
    };
    go(Vec3(24.0, 24.0, 24.0 + rho + R - 2.0));
    go(Vec3(30.0, 24.0, 24.0 + rho + R - 2.5));
    const double v1 = volume_cells(m);
    const std::size_t disagree1 = clay_set_disagreement(m, clay_whole_box(m.lattice));
    // The dent depth reached at the tool's last position.
    const float top = top_of(m, 30, 24);
    std::printf(
        "push stroke: %zu segments, volume %.1f -> %.1f cells^3 (%.3f%%), top under the tool %.2f (surface was "
        "%.2f), set disagreement %zu -> %zu nodes\n",
        segments, v0, v1, 100.0 * (v1 - v0) / v0, top, std::sqrt(rho * rho - 36.0) + 24.0, disagree0, disagree1);
    EXPECT_LT(std::fabs(v1 - v0) / v0, 0.02);
    EXPECT_LT(top, std::sqrt(rho * rho - 36.0) + 24.0 - 0.5);  // it dented
    EXPECT_LE(disagree1, disagree0 + 16);
    // Invariants: sorted, disjoint, non-touching, finite.
    for (const RaySet& s : m.sets)
        for (const auto& ray : s.rays)
            for (std::size_t i = 0; i < ray.size(); ++i) {
                ASSERT_TRUE(std::isfinite(ray[i].enter) && std::isfinite(ray[i].exit));
                ASSERT_LT(ray[i].enter, ray[i].exit);
                if (i > 0) {
                    ASSERT_LT(ray[i - 1].exit, ray[i].enter);
                }
            }
}

// Moves the tool from `p` to `to` in segments of `step` cells, applying `op` on each (a 1 kHz hand on 1 mm cells).
void stroke_to(TriDexel& m, ToolOp op, Vec3& p, const Vec3& to, double R, double step = 0.05) {
    const int n = std::max(1, static_cast<int>(std::ceil(glm::length(to - p) / step)));
    for (int k = 1; k <= n; ++k) {
        const Vec3 q = p + (to - p) * (static_cast<double>(k) / n);
        apply_clay(m, clay_sweep(op, p, q, R));
        p = q;
    }
}

TEST(ClayPull, PushThenPullOfTheSameSpotReturnsNearTheStart) {
    const double z0 = 20.3, R = 3.0, D = 2.0;
    TriDexel m = from_implicit(cube_lattice(48), slab(z0));
    const TriDexel start = m;
    const double v0 = volume_cells(m);
    // Press D cells into the face from touching, lift off (push does not pull), then touch the dent's floor and pull
    // back out by D.
    const Vec3 touch(24.2, 24.3, z0 + R);
    Vec3 p = touch;
    stroke_to(m, ToolOp::kPush, p, touch - Vec3(0.0, 0.0, D), R);
    const double dent_top = top_of(m, 24, 24);
    const double dent_moved = clay_max_displacement_cells(start, m);
    stroke_to(m, ToolOp::kPush, p, touch + Vec3(0.0, 0.0, 2.0), R);
    EXPECT_NEAR(top_of(m, 24, 24), dent_top, 1e-6);  // withdrawing a push leaves the dent
    p = touch - Vec3(0.0, 0.0, D);
    stroke_to(m, ToolOp::kPull, p, touch, R);
    const double back = clay_max_displacement_cells(start, m);
    const double dv = volume_cells(m) - v0;
    double worst = 0.0;
    for (int j = 6; j <= 42; ++j)
        for (int i = 6; i <= 42; ++i)
            worst = std::max(worst, std::fabs(static_cast<double>(top_of(m, i, j)) - top_of(start, i, j)));
    std::printf("push %.1f cells then pull back: dent %.2f cells (surface moved %.2f), after the pull the surface is "
                "within %.3f cells of the start (top crossings %.3f), volume change %.3f cells^3 (%.4f%%)\n",
                D, z0 - dent_top, dent_moved, back, worst, dv, 100.0 * dv / v0);
    EXPECT_NEAR(dent_top, z0 - D, 0.5);
    EXPECT_LT(back, 1.0);
    EXPECT_LT(worst, 1.0);
    EXPECT_LT(std::fabs(dv), 0.25 * M_PI * R * R);  // within a quarter cell over the tool's footprint
}

TEST(ClayPull, TheSurfaceFollowsTheToolOutAndNeverPassesIt) {
    const double z0 = 20.3, R = 3.0;
    TriDexel m = from_implicit(cube_lattice(48), slab(z0));
    const TriDexel start = m;
    const double v0 = volume_cells(m);
    const double r = kClayInfluence * R;
    // Held still, pressed in, or slid along while touching: nothing moves.
    Vec3 p(24.0, 24.0, z0 + R);
    EXPECT_EQ(apply_clay(m, clay_sweep(ToolOp::kPull, p, p, R)).rays.rays_changed, 0u);
    EXPECT_EQ(apply_clay(m, clay_sweep(ToolOp::kPull, p, p - Vec3(0.0, 0.0, 0.5), R)).rays.rays_changed, 0u);
    EXPECT_EQ(apply_clay(m, clay_sweep(ToolOp::kPull, p, p + Vec3(1.0, 0.0, 0.0), R)).rays.rays_changed, 0u);
    // Not touching where the motion starts: no grip.
    const Vec3 above = p + Vec3(0.0, 0.0, 1.0);
    EXPECT_EQ(apply_clay(m, clay_sweep(ToolOp::kPull, above, above + Vec3(0.0, 0.0, 1.0), R)).rays.rays_changed, 0u);
    // Draw the tool 3 cells out: the face under it follows to the ball's bottom, with Popescu's falloff around it.
    stroke_to(m, ToolOp::kPull, p, Vec3(24.0, 24.0, z0 + R + 3.0), R);
    const double peak = top_of(m, 24, 24);
    std::printf("pull 3 cells out: peak %.3f cells above the face (the ball's bottom at 3), volume %.4f%%\n",
                peak - z0, 100.0 * (volume_cells(m) - v0) / v0);
    EXPECT_NEAR(peak, z0 + 3.0, 0.5);
    EXPECT_LE(peak, z0 + 3.0 + 0.05);  // never beyond the tool
    for (int i = 14; i <= 34; ++i) {
        const double d = std::fabs(i - 24.0);
        const double bump = top_of(m, i, 24) - z0;
        if (d < 0.5 * r) {
            EXPECT_GT(bump, 0.5) << i;  // raised under the tool
        }
        if (d > r + kClayRimWidth * r + 1.0) {
            EXPECT_NEAR(bump, 0.0, 1e-6) << i;  // untouched beyond the moat
        }
    }
    EXPECT_LT(std::fabs(volume_cells(m) - v0) / v0, 0.002);
    // A fast hand: 2 cells per segment still keeps the grip.
    TriDexel f = start;
    Vec3 q(24.0, 24.0, z0 + R);
    stroke_to(f, ToolOp::kPull, q, Vec3(24.0, 24.0, z0 + R + 4.0), R, 2.0);
    EXPECT_NEAR(top_of(f, 24, 24), z0 + 4.0, 0.6);
}

TEST(ClaySmooth, PlaneIsLeftAlone) {
    const double z0 = 20.3;
    TriDexel m = from_implicit(cube_lattice(48), slab(z0));
    const TriDexel before = m;
    Vec3 p(20.0, 24.0, z0 + 3.0);
    for (int k = 0; k < 20; ++k) {
        const Vec3 q = p + Vec3(0.5, 0.0, 0.0);
        apply_clay(m, clay_sweep(ToolOp::kSmooth, p, q, 4.0));
        p = q;
    }
    double worst = 0.0;
    for (int j = 5; j < 44; ++j)
        for (int i = 5; i < 44; ++i)
            worst = std::max(worst, std::fabs(static_cast<double>(top_of(m, i, j)) - top_of(before, i, j)));
    std::printf("smooth of a plane: largest crossing move %.2e cells\n", worst);
    EXPECT_LT(worst, 1e-3);
}

/// Applies one row of smooth sweeps: sweep by sweep (apply_clay) or in groups (apply_clay_batch, clay_smooth_group).
void smooth_row(TriDexel& m, const std::vector<Sweep>& row, bool grouped) {
    if (grouped) {
        apply_clay_batch(m, row);
        return;
    }
    for (const Sweep& s : row) apply_clay(m, s);
}

// A slab whose top is a sawtooth along x (period 4 cells, 1.2 cells peak to peak); passes of the tool along x
// over the middle rows, the tool's centre riding 2.6 cells above the mean surface (R = 3).
void sawtooth_flattens(bool grouped) {
    const double z0 = 20.3, amp = 0.6;
    auto saw = [&](double x) {
        const double f = x / 4.0 - std::floor(x / 4.0);  // 0..1
        return amp * (f < 0.5 ? 4.0 * f - 1.0 : 3.0 - 4.0 * f);
    };
    TriDexel m = from_implicit(cube_lattice(48), [&](double x, double y, double z) {
        return std::max({4.4 - x, x - 43.6, 4.4 - y, y - 43.6, 4.4 - z, z - (z0 + saw(x))});
    });
    auto spread = [&] {  // peak to peak of the Z rays' tops over the brushed middle
        float lo = 1e30f, hi = -1e30f;
        for (int j = 22; j <= 26; ++j)
            for (int i = 18; i <= 30; ++i) lo = std::min(lo, top_of(m, i, j)), hi = std::max(hi, top_of(m, i, j));
        return static_cast<double>(hi - lo);
    };
    const double v0 = volume_cells(m);
    std::vector<double> s{spread()};
    for (int pass = 0; pass < 6; ++pass) {
        for (double y = 21.0; y <= 27.0; y += 1.0) {
            Vec3 p(14.0, y, z0 + 2.6);
            std::vector<Sweep> row;
            while (p.x < 34.0) {
                const Vec3 q = p + Vec3(0.25, 0.0, 0.0);
                row.push_back(clay_sweep(ToolOp::kSmooth, p, q, 3.0));
                p = q;
            }
            smooth_row(m, row, grouped);
        }
        s.push_back(spread());
    }
    std::printf("smooth of a sawtooth (%s): peak to peak", grouped ? "grouped" : "sweep by sweep");
    for (double x : s) std::printf(" %.3f", x);
    std::printf(" cells; volume %.4f%%\n", 100.0 * (volume_cells(m) - v0) / v0);
    EXPECT_LT(s.back(), 0.35 * s.front());
    for (std::size_t k = 1; k < s.size(); ++k) EXPECT_LE(s[k], s[k - 1] + 0.02) << "pass " << k;
    EXPECT_LT(std::fabs(volume_cells(m) - v0) / v0, 0.01);
}

TEST(ClaySmooth, SawtoothFlattensPassByPass) { sawtooth_flattens(false); }
TEST(ClaySmooth, SawtoothFlattensPassByPassGrouped) { sawtooth_flattens(true); }

void noisy_sphere_gets_smoother(bool grouped) {
    const double c[3] = {24.0, 24.0, 24.0}, rho = 15.0, amp = 0.7;
    TriDexel m = from_implicit(cube_lattice(48), [&](double x, double y, double z) {
        const double dx = x - c[0], dy = y - c[1], dz = z - c[2];
        const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
        const double noise = amp * std::sin(1.9 * dx) * std::sin(2.3 * dy) * std::sin(1.7 * dz + 0.4);
        return r - (rho + noise);
    });
    const double v0 = volume_cells(m);
    const double rms0 = clay_test::radial_rms(m, c, rho, 3.0, 0.6), ang0 = clay_test::normal_deviation_deg(m, c, 0.6);
    const std::size_t disagree0 = clay_set_disagreement(m, clay_whole_box(m.lattice));
    // Brush the top cap: rows across it, the tool centre just touching the surface.
    const double R = 3.0;
    double worst_stroke = 0.0;
    for (int pass = 0; pass < 3; ++pass)
        for (double y = 16.0; y <= 32.0; y += 2.0) {
            const double vs = volume_cells(m);
            Vec3 p(16.0, y, 0.0);
            auto height = [&](double x) {
                const double h2 = rho * rho - (x - c[0]) * (x - c[0]) - (y - c[1]) * (y - c[1]);
                return c[2] + std::sqrt(std::max(h2, 0.0)) + R - 0.3;
            };
            p.z = height(p.x);
            std::vector<Sweep> row;
            while (p.x < 32.0) {
                Vec3 q(p.x + 0.25, y, 0.0);
                q.z = height(q.x);
                row.push_back(clay_sweep(ToolOp::kSmooth, p, q, R));
                p = q;
            }
            smooth_row(m, row, grouped);
            worst_stroke = std::max(worst_stroke, std::fabs(volume_cells(m) - vs) / vs);
        }
    const double v1 = volume_cells(m);
    const double rms1 = clay_test::radial_rms(m, c, rho, 3.0, 0.6), ang1 = clay_test::normal_deviation_deg(m, c, 0.6);
    const std::size_t disagree1 = clay_set_disagreement(m, clay_whole_box(m.lattice));
    std::printf(
        "smooth of a noisy sphere (%s): radial rms %.3f -> %.3f cells, normal deviation %.2f -> %.2f deg, volume "
        "%.3f%% (worst stroke %.3f%%), set disagreement %zu -> %zu nodes\n",
        grouped ? "grouped" : "sweep by sweep", rms0, rms1, ang0, ang1, 100.0 * (v1 - v0) / v0, 100.0 * worst_stroke,
        disagree0, disagree1);
    EXPECT_LT(worst_stroke, 0.01);
    EXPECT_LT(ang1, 0.85 * ang0);
    EXPECT_LT(rms1, rms0);
    EXPECT_LE(disagree1, disagree0 + 16);
}

TEST(ClaySmooth, NoisySphereGetsSmootherAndKeepsItsVolume) { noisy_sphere_gets_smoother(false); }
TEST(ClaySmooth, NoisySphereGetsSmootherAndKeepsItsVolumeGrouped) { noisy_sphere_gets_smoother(true); }

TEST(ClaySweep, BoundsCoverTheChangedRaysAndUndoRestoresExactly) {
    const double ctr[3] = {24.0, 24.0, 24.0}, rho = 14.0;
    TriDexel m = from_implicit(cube_lattice(48), [&](double x, double y, double z) {
        return std::sqrt((x - ctr[0]) * (x - ctr[0]) + (y - ctr[1]) * (y - ctr[1]) + (z - ctr[2]) * (z - ctr[2])) - rho;
    });
    const TriDexel start = m;
    UndoHistory history(m.lattice);
    std::vector<Sweep> stroke;
    Vec3 p(24.0, 24.0, 24.0 + rho + 3.0 - 0.2);
    for (int k = 0; k < 30; ++k) {
        const Vec3 q = p + Vec3(0.1, 0.02, -0.03);
        stroke.push_back(clay_sweep(k % 2 ? ToolOp::kSmooth : ToolOp::kPush, p, q, 3.0));
        p = q;
    }
    for (const Sweep& s : stroke) {
        history.capture(m, std::span<const Sweep>(&s, 1));
        std::vector<RayImage> before;
        apply_clay(m, s, &before);
        const Aabb box = clay_bounds(m.lattice, s);
        for (const RayImage& r : before) {  // every changed ray lies under the sweep's bounds
            const RaySet& set = m.sets[r.axis];
            const int u = static_cast<int>(r.index % set.nu), v = static_cast<int>(r.index / set.nu);
            const int ua = (r.axis + 1) % 3, va = (r.axis + 2) % 3;
            EXPECT_GE(u, box.lo[ua] / kCell - 1e-6);
            EXPECT_LE(u, box.hi[ua] / kCell + 1e-6);
            EXPECT_GE(v, box.lo[va] / kCell - 1e-6);
            EXPECT_LE(v, box.hi[va] / kCell + 1e-6);
        }
    }
    ASSERT_NE(history.end_stroke(m), 0u);
    const UndoHistory::Change c = history.undo(m, [&](std::span<const RayImage> rays, const Aabb&) {
        for (const RayImage& r : rays) m.sets[r.axis].rays[r.index] = r.intervals;
    });
    EXPECT_GT(c.rays, 0u);
    for (int a = 0; a < 3; ++a)
        for (std::size_t i = 0; i < m.sets[a].rays.size(); ++i) {
            const auto& x = m.sets[a].rays[i];
            const auto& y = start.sets[a].rays[i];
            ASSERT_EQ(x.size(), y.size()) << a << " " << i;
            for (std::size_t k = 0; k < x.size(); ++k) {
                ASSERT_EQ(x[k].enter, y[k].enter);
                ASSERT_EQ(x[k].exit, y[k].exit);
            }
        }
}

TEST(ClaySweep, ALongPushGoesInPiecesAndStaysCheap) {
    // A 30-cell jump through a slab's top, pressing 1 cell: applied as 2-cell pieces, each on a small box.
    const double z0 = 20.3;
    TriDexel m = from_implicit(cube_lattice(48), slab(z0));
    const double v0 = volume_cells(m);
    const ClayStats st =
        apply_clay(m, clay_sweep(ToolOp::kPush, Vec3(9.0, 24.0, z0 + 2.0), Vec3(39.0, 24.0, z0 + 2.0), 3.0));
    EXPECT_GT(st.rays.rays_changed, 0u);
    EXPECT_LT(top_of(m, 24, 24), z0 - 0.5);  // dented along the path
    EXPECT_LT(std::fabs(volume_cells(m) - v0) / v0, 0.02);
}

TEST(ClaySweep, RefusesBadInput) {
    TriDexel m = from_implicit(cube_lattice(16), [](double, double, double z) { return z - 8.3; });
    Sweep s = clay_sweep(ToolOp::kPush, Vec3(8.0), Vec3(8.0), 2.0);
    s.tool.radius_m = -1.0;
    EXPECT_THROW(apply_clay(m, s), Error);
    s = clay_sweep(ToolOp::kPush, Vec3(NAN), Vec3(8.0), 2.0);
    EXPECT_THROW(apply_clay(m, s), Error);
    s = clay_sweep(ToolOp::kSubtract, Vec3(8.0), Vec3(8.0), 2.0);
    EXPECT_THROW(apply_clay(m, s), Error);
}

}  // namespace
}  // namespace tridex::compute
