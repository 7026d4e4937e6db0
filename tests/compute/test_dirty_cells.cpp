// tests/compute/test_dirty_cells.cpp - what a Boolean marks for re-contouring: the changed span of each ray
// operation (ChangedSpan) holds exactly the interval ends it changed, and a sweep marks the cells within the
// dirty reach of its changed ends, not of its whole swept box.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>
#include <vector>

#include "compute/mesh/scan_convert.hpp"
#include "compute/model/interval_ops.hpp"
#include "compute/tools/clay_push.hpp"
#include "compute/tools/sweep.hpp"
#include "compute/tools/sweep_parallel.hpp"
#include "core/primitives.hpp"

using namespace tridex;
using namespace tridex::compute;

namespace {

/// The interval ends of a ray as (depth, material, is_exit), sorted.
std::vector<std::tuple<float, int, int>> ends_of(const std::vector<Interval>& ray) {
    std::vector<std::tuple<float, int, int>> e;
    for (const Interval& iv : ray) {
        e.emplace_back(iv.enter, iv.enter_material, 0);
        e.emplace_back(iv.exit, iv.exit_material, 1);
    }
    std::sort(e.begin(), e.end());
    return e;
}

/// Depths of the ends in one ray and not in the other (either way).
std::vector<float> changed_ends(const std::vector<Interval>& before, const std::vector<Interval>& after) {
    const auto a = ends_of(before), b = ends_of(after);
    std::vector<std::tuple<float, int, int>> d;
    std::set_symmetric_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(d));
    std::vector<float> out;
    for (const auto& x : d) out.push_back(std::get<0>(x));
    return out;
}

/// A random valid ray: sorted, disjoint, non-touching intervals on [0, 40] with materials 0..3.
std::vector<Interval> random_ray(std::mt19937& rng) {
    std::uniform_real_distribution<float> gap(0.1f, 6.0f);
    std::uniform_int_distribution<int> count(0, 5), mat(0, 3);
    std::vector<Interval> r;
    float t = gap(rng);
    for (int i = count(rng); i > 0; --i) {
        const float a = t, b = t + gap(rng);
        r.push_back({a, b, static_cast<std::uint8_t>(mat(rng)), static_cast<std::uint8_t>(mat(rng))});
        t = b + gap(rng);
    }
    return r;
}

TEST(ChangedSpan, HoldsExactlyTheEndsEachOperationChanged) {
    // Random rays and random spans, subtracted, added and painted: the span is empty exactly when nothing
    // changed, holds every end that was removed, made, moved or repainted, and both its bounds are such ends.
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> at(-2.0f, 42.0f), len(0.0f, 12.0f);
    std::uniform_int_distribution<int> op(0, 2), mat(0, 3);
    int changes[3] = {0, 0, 0};
    for (int trial = 0; trial < 3000; ++trial) {
        std::vector<Interval> ray = random_ray(rng);
        const std::vector<Interval> before = ray;
        const float t0 = at(rng), t1 = t0 + len(rng);
        const int which = op(rng);
        const std::uint8_t m = static_cast<std::uint8_t>(mat(rng));
        ChangedSpan span;
        const bool changed = which == 0   ? subtract_interval_changed(ray, t0, t1, m, &span)
                             : which == 1 ? union_interval_changed(ray, t0, t1, m, &span)
                                          : paint_interval_changed(ray, t0, t1, m, &span);
        SCOPED_TRACE(::testing::Message() << "trial " << trial << " op " << which << " [" << t0 << ", " << t1 << "]");
        const std::vector<float> ends = changed_ends(before, ray);
        ASSERT_EQ(changed, !ends.empty());
        ASSERT_EQ(span.empty(), !changed);
        // The span of two versions of the ray (what clay reports) holds the same ends.
        const ChangedSpan diff = changed_span(before, ray);
        ASSERT_EQ(diff.empty(), !changed);
        for (const float e : ends) {
            EXPECT_LE(diff.lo, e);
            EXPECT_GE(diff.hi, e);
        }
        if (!changed) continue;
        ++changes[which];
        for (const float e : ends) {
            EXPECT_LE(span.lo, e);
            EXPECT_GE(span.hi, e);
        }
        EXPECT_NE(std::find(ends.begin(), ends.end(), span.lo), ends.end()) << "the span starts before the change";
        EXPECT_NE(std::find(ends.begin(), ends.end(), span.hi), ends.end()) << "the span ends after the change";
    }
    for (const int c : changes) EXPECT_GT(c, 200);  // every operation changed rays often enough to be seen
}

/// A box from 4.5 cells to `top` (grid units, every axis) on a cube lattice of `cells`, dirty flags clear.
TriDexel box_model(int cells, double top) {
    Lattice L;
    L.origin_m = Vec3(0.3, -0.2, 0.1);
    L.cell_m = 0.001;
    L.cells = {cells, cells, cells};
    TriDexel m = TriDexel::empty(L, std::size_t{1} << 30);
    scan_convert(box_mesh(Aabb{L.to_world(Vec3(4.5)), L.to_world(Vec3(top))}), m);
    m.clear_dirty();
    return m;
}

/// The grid box of every interval end that differs between two models.
void changed_box(const TriDexel& a, const TriDexel& b, Vec3& lo, Vec3& hi) {
    lo = Vec3(INFINITY);
    hi = Vec3(-INFINITY);
    for (int s = 0; s < 3; ++s)
        for (int v = 0; v < a.sets[s].nv; ++v)
            for (int u = 0; u < a.sets[s].nu; ++u)
                for (const float e : changed_ends(a.sets[s].ray(u, v), b.sets[s].ray(u, v))) {
                    Vec3 p;
                    p[s] = e;
                    p[(s + 1) % 3] = u;
                    p[(s + 2) % 3] = v;
                    lo = glm::min(lo, p);
                    hi = glm::max(hi, p);
                }
}

/// Expects every cell within kDirtyReachCells of an interval end that differs between `before` and `after`
/// to be marked in `after`'s flags (its tile whole, or partial with the cell in its box). Returns the number
/// of changed ends.
std::size_t expect_changed_ends_covered(const TriDexel& before, const TriDexel& after) {
    const TileGrid& g = after.tiles;
    const int R = TriDexel::kDirtyReachCells;
    std::size_t ends = 0, misses = 0;
    for (int s = 0; s < 3; ++s)
        for (int v = 0; v < before.sets[s].nv; ++v)
            for (int u = 0; u < before.sets[s].nu; ++u)
                for (const float e : changed_ends(before.sets[s].ray(u, v), after.sets[s].ray(u, v))) {
                    ++ends;
                    int p[3];
                    p[s] = static_cast<int>(std::floor(e));
                    p[(s + 1) % 3] = u;
                    p[(s + 2) % 3] = v;
                    int lo[3], hi[3];
                    for (int a = 0; a < 3; ++a) {
                        lo[a] = std::max(0, p[a] - R);
                        hi[a] = std::min(after.lattice.cells[a] - 1, p[a] + R);
                    }
                    for (int z = lo[2]; z <= hi[2]; ++z)
                        for (int y = lo[1]; y <= hi[1]; ++y)
                            for (int x = lo[0]; x <= hi[0]; ++x) {
                                const std::size_t t = g.index(x / 16, y / 16, z / 16);
                                const CellBox* box = g.partial_cells(t);
                                const bool ok =
                                    g.dirty[t] != 0 &&
                                    (box == nullptr || (x >= box->lo[0] && x <= box->hi[0] && y >= box->lo[1] &&
                                                        y <= box->hi[1] && z >= box->lo[2] && z <= box->hi[2]));
                                if (!ok && ++misses <= 5)
                                    ADD_FAILURE() << "cell " << x << "," << y << "," << z << " near changed end " << e
                                                  << " of ray set " << s << " (" << u << ", " << v << ") is not marked";
                            }
                }
    EXPECT_EQ(misses, 0u);
    return ends;
}

TEST(DirtyCells, ABallDippingIntoTheTopFaceMarksTheCellsAroundWhatItCut) {
    // A 6-cell ball whose centre sits 4 cells above the box's top face cuts a dimple 2 cells deep: the cells
    // marked are those within the dirty reach of the dimple's ends, far fewer than those around the ball's box.
    const int cells = 64;
    const double top = 40.5;
    TriDexel m = box_model(cells, top);
    const TriDexel before = m;
    const Lattice& L = m.lattice;
    Sweep s;
    s.tool.kind = ToolKind::kBall;
    s.tool.radius_m = 6.0 * L.cell_m;
    s.path_m = {L.to_world(Vec3(27.3, 29.6, top + 4.0)), L.to_world(Vec3(30.1, 29.6, top + 4.0))};
    const BooleanStats st = apply_sweep(m, s);
    ASSERT_GT(st.rays_changed, 0u);
    Vec3 lo, hi;
    changed_box(before, m, lo, hi);
    // The marked cells per tile, against floor(changed ends) -/+ kDirtyReachCells clamped to the lattice.
    int want_lo[3], want_hi[3];
    for (int a = 0; a < 3; ++a) {
        want_lo[a] = std::max(0, static_cast<int>(std::floor(lo[a] - 1e-3)) - TriDexel::kDirtyReachCells);
        want_hi[a] = std::min(cells - 1, static_cast<int>(std::floor(hi[a] + 1e-3)) + TriDexel::kDirtyReachCells);
    }
    std::size_t marked_cells = 0;
    for (int tz = 0; tz < m.tiles.tiles[2]; ++tz)
        for (int ty = 0; ty < m.tiles.tiles[1]; ++ty)
            for (int tx = 0; tx < m.tiles.tiles[0]; ++tx) {
                const std::size_t t = m.tiles.index(tx, ty, tz);
                const int tile[3] = {tx, ty, tz};
                bool touches = true;
                for (int a = 0; a < 3; ++a)
                    touches = touches && want_lo[a] <= tile[a] * 16 + 15 && want_hi[a] >= tile[a] * 16;
                ASSERT_EQ(m.tiles.dirty[t] != 0, touches) << "tile " << tx << "," << ty << "," << tz;
                if (!touches) continue;
                const CellBox* box = m.tiles.partial_cells(t);
                ASSERT_NE(box, nullptr);
                std::size_t n = 1;
                for (int a = 0; a < 3; ++a) {
                    EXPECT_EQ(box->lo[a], std::max(want_lo[a], tile[a] * 16)) << "axis " << a;
                    EXPECT_EQ(box->hi[a], std::min(want_hi[a], tile[a] * 16 + 15)) << "axis " << a;
                    n *= static_cast<std::size_t>(box->hi[a] - box->lo[a] + 1);
                }
                marked_cells += n;
            }
    expect_changed_ends_covered(before, m);
    // Along z the dimple's ends span cells 38..40, so 11 cells are marked; the ball's box spans 38..50, 21 cells.
    EXPECT_EQ(want_hi[2] - want_lo[2] + 1, 11);
    // The ball's box (x 21..36, y 23..35, z 38..50) widened by the reach: 24 x 21 x 21 cells.
    const std::size_t ball_box_cells = std::size_t{24} * 21 * 21;
    EXPECT_LT(marked_cells, ball_box_cells / 2) << marked_cells;
}

TEST(DirtyCells, AClayPushMarksTheCellsAroundEveryEndItMoved) {
    // A push into the top face of a box moves the surface within its radius of influence and the rim around it:
    // every cell within the dirty reach of every end that moved is marked, and fewer cells than the field's box.
    const int cells = 64;
    const TriDexel start = box_model(cells, 40.5);
    TriDexel m = start;
    const Lattice& L = m.lattice;
    Sweep s;
    s.op = ToolOp::kPush;
    s.tool.kind = ToolKind::kBall;
    s.tool.radius_m = 5.0 * L.cell_m;
    s.path_m = {L.to_world(Vec3(28.3, 30.6, 44.0)), L.to_world(Vec3(33.1, 30.6, 43.5))};
    const GridSweep g = to_grid_sweep(L, s);
    const ClayStats st = clay_push(m, g);
    ASSERT_GT(st.rays.rays_changed, 0u);
    EXPECT_GT(expect_changed_ends_covered(start, m), 50u);
    for (std::size_t t = 0; t < m.tiles.count(); ++t) EXPECT_NE(m.tiles.dirty[t], TileGrid::kWhole) << "tile " << t;
}

TEST(DirtyCells, AllCoresBatchesMarkTheCellsAroundEveryChangedEnd) {
    // A batch of sweeps on all cores and the same sweeps one by one give the same model and the same marks
    // (a box per sweep, so the marks follow the path), and every cell within the dirty reach of every changed
    // end is marked.
    const int cells = 64;
    const TriDexel start = box_model(cells, cells - 4.5);
    TriDexel a = start, b = start;
    const Lattice& L = a.lattice;
    std::vector<Sweep> batch;
    for (int k = 0; k < 12; ++k) {
        Sweep s;
        s.tool.kind = ToolKind::kBall;
        s.tool.radius_m = 5.0 * L.cell_m;
        s.op = k % 4 == 3 ? ToolOp::kPaint : ToolOp::kSubtract;
        s.material = 2;
        s.path_m = {L.to_world(Vec3(12.0 + 3.0 * k, 20.0 + 2.0 * k, cells - 6.0)),
                    L.to_world(Vec3(15.0 + 3.0 * k, 22.0 + 2.0 * k, cells - 6.5))};
        batch.push_back(s);
    }
    for (const Sweep& s : batch) apply_sweep(a, s);
    apply_sweeps_parallel(b, batch, 2);
    Vec3 lo, hi;
    changed_box(a, b, lo, hi);
    EXPECT_GT(lo.x, hi.x) << "the two paths' models differ";
    EXPECT_EQ(a.tiles.dirty, b.tiles.dirty);
    for (std::size_t t = 0; t < a.tiles.count(); ++t) {
        const CellBox *pa = a.tiles.partial_cells(t), *pb = b.tiles.partial_cells(t);
        ASSERT_EQ(pa == nullptr, pb == nullptr) << "tile " << t;
        if (pa == nullptr) continue;
        EXPECT_EQ(pa->lo, pb->lo) << "tile " << t;
        EXPECT_EQ(pa->hi, pb->hi) << "tile " << t;
    }
    EXPECT_GT(expect_changed_ends_covered(start, a), 1000u);
    std::size_t partial = 0;
    for (std::size_t t = 0; t < b.tiles.count(); ++t) partial += b.tiles.partial_cells(t) != nullptr ? 1 : 0;
    EXPECT_GT(partial, 0u);
}

}  // namespace
