// tests/stress/test_stress_booleans.cpp - half a million random swept Booleans on box workpieces, with the
// model's invariants checked after every batch.
//
// CpuReference (one test per N = 64, 80, 100, 128; 125k segments each = 0.5M by default, 10M in the long variant): random segments of mixed
// operations (subtract, union, paint), ball and flat-end tools (radius 0.3..8 cells, log-uniform; some
// whole cells), random lengths (zero to 24 cells, log-uniform, so the cost per segment does not grow with N), starts on and off the lattice,
// some snapped to nodes, applied with apply_sweep in batches of 200..2000. Each batch is subtract-only,
// union-only, paint-only or mixed. After each batch, on every ray a sweep's footprint holds (and on all
// rays every 25 batches and at the end): ends finite, enter < exit, sorted, disjoint, non-touching.
// Per batch type: subtract-only -> each touched ray's new solid lies inside its old one and the volume
// does not grow; union-only -> the old solid lies inside the new (no interval lost) and the volume does
// not shrink; paint-only -> depths and interval counts identical, volume bit-identical, and every end's
// material as the exact (double) chords say (stress_paint.hpp: inside some sweep's exact solid by more than
// kPaintMargin = 1e-3 cells in 3D -> the material of the last such sweep in batch order; farther than that
// from every sweep -> unchanged). Materials come from a sparse set of ids, and after every batch (any kind) every end of a
// touched ray (every ray at the full checks) carries an id that was used (0 or a sweep's).
// GpuVsCpu: 50k segments (1M in the long variant) of the same kind at N = 64 through GpuSculptor (small spill pool, so it
// compacts and grows) and apply_sweep side by side: after each batch the mirror's touched rays equal
// the CPU's bit for bit, every 20 batches (and at the end) the whole downloaded GPU model does.
// Build with -DTRIDEX_LONG_TESTS=ON for the long variant (label "long"): 10x the segments, N up to 256.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <random>
#include <span>
#include <vector>

#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/tools/sweep.hpp"
#include "compute/model/volume.hpp"
#include "core/error.hpp"
#include "gpu/context.hpp"
#include "stress_common.hpp"
#include "stress_paint.hpp"

using namespace tridex;
using namespace tridex::compute;

namespace {

#ifdef TRIDEX_STRESS_LONG
constexpr std::size_t kSegmentsPerN = 2'500'000;
constexpr std::size_t kGpuSegments = 1'000'000;
const std::vector<int> kSizes = {64, 128, 192, 256};
#else
constexpr std::size_t kSegmentsPerN = 125'000;  // 4 sizes: half a million segments
constexpr std::size_t kGpuSegments = 50'000;
const std::vector<int> kSizes = {64, 80, 100, 128};
#endif
constexpr int kFullCheckEvery = 25;
constexpr double kPaintMargin = 1e-3;  // cells (3D): ends nearer than this to a sweep's exact surface are not judged
// Sweep materials: a sparse set, so a wrong or garbage id is very likely not one of them.
constexpr std::uint8_t kMaterialIds[8] = {3, 17, 42, 77, 128, 199, 231, 254};

enum class BatchKind { kSubtract, kUnion, kPaint, kMixed };
const char* kind_name(BatchKind k) {
    return k == BatchKind::kSubtract ? "subtract" : k == BatchKind::kUnion ? "union" : k == BatchKind::kPaint ? "paint" : "mixed";
}

/// Random segments on an n^3 lattice: strokes (a segment usually starts where the last ended).
class SegmentSource {
public:
    SegmentSource(const Lattice& L, std::uint64_t seed) : L_(L), rng_(seed) { p_ = random_point(); }

    Sweep next(BatchKind kind) {
        Sweep s;
        const double pick = uni(0.0, 1.0);
        s.op = kind == BatchKind::kSubtract ? ToolOp::kSubtract
               : kind == BatchKind::kUnion  ? ToolOp::kUnion
               : kind == BatchKind::kPaint  ? ToolOp::kPaint
               : pick < 0.55                ? ToolOp::kSubtract
               : pick < 0.85                ? ToolOp::kUnion
                                            : ToolOp::kPaint;
        s.material = kMaterialIds[rng_() % 8];
        double r = std::exp(uni(std::log(0.3), std::log(8.0)));  // cells, log-uniform 0.3..8
        if (uni(0.0, 1.0) < 0.15) r = std::max(1.0, std::round(r));
        const bool flat = uni(0.0, 1.0) < 0.3;
        s.tool = SweepTool{flat ? ToolKind::kFlatEnd : ToolKind::kBall, r * L_.cell_m, uni(1.0, 12.0) * L_.cell_m};
        s.axis = uni(0.0, 1.0) < 0.5 ? Vec3(0.0, 0.0, 1.0) : Vec3(uni(-1, 1), uni(-1, 1), uni(-1, 1));
        if (!(glm::length(s.axis) > 1e-3)) s.axis = Vec3(1.0, 0.0, 0.0);
        if (uni(0.0, 1.0) < 0.2) p_ = random_point();  // a new stroke
        Vec3 a = p_;
        const double len = uni(0.0, 1.0) < 0.05 ? 0.0 : std::exp(uni(std::log(0.01), std::log(24.0)));
        Vec3 dir(uni(-1, 1), uni(-1, 1), uni(-1, 1));
        if (!(glm::length(dir) > 1e-3)) dir = Vec3(0.0, 1.0, 0.0);
        Vec3 b = a + glm::normalize(dir) * len;
        if (uni(0.0, 1.0) < 0.1) b = glm::round(b);  // on a lattice node
        b = glm::clamp(b, Vec3(-10.0), Vec3(L_.cells[0] + 10.0));
        s.path_m = Segment{L_.to_world(a), L_.to_world(b)};
        p_ = b;
        return s;
    }
    BatchKind next_kind() {
        const double pick = uni(0.0, 1.0);
        return pick < 0.3 ? BatchKind::kSubtract : pick < 0.5 ? BatchKind::kUnion : pick < 0.6 ? BatchKind::kPaint : BatchKind::kMixed;
    }
    std::size_t next_batch_size(std::size_t lo, std::size_t hi) { return lo + rng_() % (hi - lo + 1); }

private:
    double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
    Vec3 random_point() {
        Vec3 g(uni(-6.0, L_.cells[0] + 6.0), uni(-6.0, L_.cells[1] + 6.0), uni(-6.0, L_.cells[2] + 6.0));
        if (uni(0.0, 1.0) < 0.1) g = glm::round(g);
        return g;
    }
    Lattice L_;
    std::mt19937_64 rng_;
    Vec3 p_{0.0};
};

/// The rays (set, index) whose node lies in the footprint of some sweep of `batch`; each listed once.
class TouchedRays {
public:
    explicit TouchedRays(const TriDexel& m) {
        for (int a = 0; a < 3; ++a) mark_[a].assign(m.sets[a].rays.size(), 0u);
    }
    const std::vector<std::pair<int, std::size_t>>& collect(const TriDexel& m, std::span<const Sweep> batch) {
        ++epoch_;
        list_.clear();
        for (const Sweep& s : batch) {
            const GridSweep g = to_grid_sweep(m.lattice, s);
            for (int a = 0; a < 3; ++a) {
                int u0, u1, v0, v1;
                if (!sweep_footprint(g, m.sets[a], u0, u1, v0, v1)) continue;
                for (int v = v0; v <= v1; ++v)
                    for (int u = u0; u <= u1; ++u) {
                        const std::size_t i = static_cast<std::size_t>(u) + static_cast<std::size_t>(m.sets[a].nu) * v;
                        if (mark_[a][i] != epoch_) {
                            mark_[a][i] = epoch_;
                            list_.emplace_back(a, i);
                        }
                    }
            }
        }
        return list_;
    }

private:
    std::array<std::vector<std::uint32_t>, 3> mark_;
    std::uint32_t epoch_ = 0;
    std::vector<std::pair<int, std::size_t>> list_;
};

/// Checks the invariants on all rays; returns the number of bad rays (reports the first few).
/// With `used`, also that every end's material id is flagged there.
std::size_t check_all_rays(const TriDexel& m, const char* what, std::size_t& max_intervals, const std::array<bool, 256>* used = nullptr) {
    std::size_t bad = 0;
    for (int a = 0; a < 3; ++a)
        for (std::size_t i = 0; i < m.sets[a].rays.size(); ++i) {
            max_intervals = std::max(max_intervals, m.sets[a].rays[i].size());
            std::string why = test::ray_violation(m.sets[a].rays[i]);
            if (why.empty() && used && test::unused_materials(m.sets[a].rays[i], *used) > 0) why = "a material id that no sweep used";
            if (!why.empty() && ++bad <= 3) ADD_FAILURE() << what << ": set " << a << " ray " << i << ": " << why;
        }
    return bad;
}

class StressBooleans : public ::testing::TestWithParam<int> {};

TEST_P(StressBooleans, CpuReferenceKeepsTheInvariantsOverRandomBatches) {
    const int n = GetParam();
    TriDexel m = test::stress_box(n, 3.5, n - 3.5);
    SegmentSource src(m.lattice, 1000u + static_cast<unsigned>(n));
    TouchedRays touched(m);
    std::vector<Sweep> batch;
    std::vector<std::vector<Interval>> before;
    std::size_t done = 0, batches = 0, bad = 0, rays_checked = 0, visited = 0, changed = 0, max_intervals = 0;
    std::size_t kind_count[4] = {}, kind_bad[4] = {};
    std::array<bool, 256> used{};
    used[0] = true;  // the workpiece's own material
    test::PaintReport paint_total;
    double apply_s = 0.0, check_s = 0.0, paint_s = 0.0;
    double volume = dexel_volume_m3(m);
    const double volume0 = volume;
    while (done < kSegmentsPerN) {
        const BatchKind kind = src.next_kind();
        const std::size_t count = std::min(kSegmentsPerN - done, src.next_batch_size(200, 2000));
        batch.clear();
        for (std::size_t k = 0; k < count; ++k) batch.push_back(src.next(kind)), used[batch.back().material] = true;
        const auto c0 = std::chrono::steady_clock::now();
        const auto& rays = touched.collect(m, batch);
        before.resize(rays.size());
        for (std::size_t k = 0; k < rays.size(); ++k) before[k] = m.sets[rays[k].first].rays[rays[k].second];
        const auto t0 = std::chrono::steady_clock::now();
        for (const Sweep& s : batch) {
            const BooleanStats st = apply_sweep(m, s);
            visited += st.rays_visited;
            changed += st.rays_changed;
        }
        const auto t1 = std::chrono::steady_clock::now();
        // Invariants on the touched rays, and per batch kind the containment of old and new solids.
        std::size_t batch_bad = 0;
        for (std::size_t k = 0; k < rays.size(); ++k) {
            const auto& now = m.sets[rays[k].first].rays[rays[k].second];
            max_intervals = std::max(max_intervals, now.size());
            std::string why = test::ray_violation(now);
            if (why.empty() && kind == BatchKind::kSubtract && !test::solid_within(now, before[k])) why = "subtract batch grew the solid";
            if (why.empty() && kind == BatchKind::kUnion && !test::solid_within(before[k], now)) why = "union batch lost solid (an interval)";
            if (why.empty() && kind == BatchKind::kPaint) {
                bool same = now.size() == before[k].size();
                for (std::size_t j = 0; same && j < now.size(); ++j)
                    same = now[j].enter == before[k][j].enter && now[j].exit == before[k][j].exit;
                if (!same) why = "paint batch moved a depth";
            }
            if (why.empty() && test::unused_materials(now, used) > 0) why = "a material id that no sweep used";
            if (!why.empty() && ++batch_bad <= 3)
                ADD_FAILURE() << "N " << n << " batch " << batches << " (" << kind_name(kind) << "): set " << rays[k].first
                              << " ray " << rays[k].second << ": " << why;
        }
        rays_checked += rays.size();
        if (kind == BatchKind::kPaint) {
            const auto p0 = std::chrono::steady_clock::now();
            const test::PaintReport p = test::check_paint_batch(m, batch, rays, before, kPaintMargin);
            if (p.bad) batch_bad += p.bad, ADD_FAILURE() << "N " << n << " batch " << batches << " (paint): " << p.bad << " wrong ends:" << p.first;
            paint_total.ends += p.ends, paint_total.painted += p.painted, paint_total.kept += p.kept;
            paint_total.undecided += p.undecided, paint_total.bad += p.bad;
            paint_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - p0).count();
        }
        const double v = dexel_volume_m3(m);
        if (kind == BatchKind::kSubtract && v > volume) ++batch_bad, ADD_FAILURE() << "N " << n << " batch " << batches << ": subtract-only batch grew the volume " << volume << " -> " << v;
        if (kind == BatchKind::kUnion && v < volume) ++batch_bad, ADD_FAILURE() << "N " << n << " batch " << batches << ": union-only batch shrank the volume " << volume << " -> " << v;
        if (kind == BatchKind::kPaint && v != volume) ++batch_bad, ADD_FAILURE() << "N " << n << " batch " << batches << ": paint-only batch changed the volume " << volume << " -> " << v;
        volume = v;
        if (++batches % kFullCheckEvery == 0) batch_bad += check_all_rays(m, "full check", max_intervals, &used);
        ++kind_count[static_cast<int>(kind)];
        if (batch_bad) ++kind_bad[static_cast<int>(kind)];
        bad += batch_bad;
        done += count;
        apply_s += std::chrono::duration<double>(t1 - t0).count();
        check_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count() +
                   std::chrono::duration<double>(t0 - c0).count();
        if (bad > 20) break;
    }
    bad += check_all_rays(m, "final check", max_intervals, &used);
    std::printf("N %d: %zu segments in %zu batches (subtract %zu, union %zu, paint %zu, mixed %zu); %.2f us/segment "
                "(apply %.1f s, checks %.1f s); rays visited/segment %.1f, changed/segment %.1f; %zu touched rays checked; "
                "max intervals on a ray %zu; intervals now %zu; volume %.4g -> %.4g m^3; bad rays %zu (by kind %zu/%zu/%zu/%zu)\n",
                n, done, batches, kind_count[0], kind_count[1], kind_count[2], kind_count[3], 1e6 * apply_s / done, apply_s,
                check_s, double(visited) / done, double(changed) / done, rays_checked, max_intervals, m.interval_count(), volume0,
                volume, bad, kind_bad[0], kind_bad[1], kind_bad[2], kind_bad[3]);
    std::printf("N %d paint materials: %zu ends checked, %zu painted (last sweep's id), %zu kept, %zu undecided "
                "(within %.0e cells of a sweep's surface, 3D), wrong %zu; material check %.1f s\n",
                n, paint_total.ends, paint_total.painted, paint_total.kept, paint_total.undecided, kPaintMargin, paint_total.bad,
                paint_s);
    EXPECT_EQ(done, kSegmentsPerN);
    EXPECT_EQ(bad, 0u);
    EXPECT_EQ(paint_total.bad, 0u);
    EXPECT_GT(paint_total.painted, 0u);
    EXPECT_GT(paint_total.kept, 0u);
    EXPECT_GT(changed, done);  // the program really cut and added material
    EXPECT_GT(kind_count[0], 0u);
    EXPECT_GT(kind_count[1], 0u);
    EXPECT_GT(kind_count[2], 0u);
}

INSTANTIATE_TEST_SUITE_P(Sizes, StressBooleans, ::testing::ValuesIn(kSizes),
                         [](const ::testing::TestParamInfo<int>& i) { return "N" + std::to_string(i.param); });

TEST(StressBooleansGpu, GpuSculptorMatchesTheCpuReferenceBitForBit) {
    gpu::Context ctx = gpu::Context::create({});
    {
        const int n = 64;
        TriDexel cpu = test::stress_box(n, 3.5, n - 3.5);
        TriDexel gpu_model = test::stress_box(n, 3.5, n - 3.5);
        GpuSculptorOptions opt;
        opt.initial_pool_chunks = 64;  // small: forces compactions and growth
        GpuSculptor sculptor(ctx, gpu_model, opt);
        SegmentSource src(cpu.lattice, 77u);
        TouchedRays touched(cpu);
        std::vector<Sweep> batch;
        std::size_t done = 0, batches = 0, bad_rays = 0, bad_full = 0, invariant_bad = 0, max_intervals = 0;
        double cpu_s = 0.0, gpu_s = 0.0;
        while (done < kGpuSegments) {
            const BatchKind kind = src.next_kind();
            const std::size_t count = std::min(kGpuSegments - done, src.next_batch_size(1, 1000));
            batch.clear();
            for (std::size_t k = 0; k < count; ++k) batch.push_back(src.next(kind));
            const auto t0 = std::chrono::steady_clock::now();
            for (const Sweep& s : batch) apply_sweep(cpu, s);
            const auto t1 = std::chrono::steady_clock::now();
            ASSERT_NO_THROW(sculptor.apply(batch)) << "batch " << batches;
            const auto t2 = std::chrono::steady_clock::now();
            cpu_s += std::chrono::duration<double>(t1 - t0).count();
            gpu_s += std::chrono::duration<double>(t2 - t1).count();
            for (const auto& [a, i] : touched.collect(cpu, batch)) {
                const auto& x = cpu.sets[a].rays[i];
                max_intervals = std::max(max_intervals, x.size());
                if (!test::same_bits(x, gpu_model.sets[a].rays[i]) && ++bad_rays <= 3)
                    ADD_FAILURE() << "batch " << batches << " set " << a << " ray " << i << ": GPU mirror differs from the CPU";
                if (!test::ray_violation(x).empty()) ++invariant_bad;
            }
            if (++batches % 20 == 0 || done + count >= kGpuSegments) {
                TriDexel down = TriDexel::empty(cpu.lattice, std::size_t{1} << 31);
                sculptor.slabs().download(down);
                for (int a = 0; a < 3; ++a)
                    for (std::size_t i = 0; i < cpu.sets[a].rays.size(); ++i)
                        if (!test::same_bits(cpu.sets[a].rays[i], down.sets[a].rays[i]) && ++bad_full <= 3)
                            ADD_FAILURE() << "batch " << batches << " set " << a << " ray " << i << ": downloaded GPU model differs";
            }
            done += count;
            if (bad_rays + bad_full > 10) break;
        }
        const GpuSculptStats& st = sculptor.stats();
        std::printf("GPU vs CPU, N %d: %zu segments in %zu batches; CPU %.2f us/segment, GPU (lavapipe) %.2f us/segment; "
                    "dispatches %llu, ray tiles %llu, rays redone on the host %llu, compactions %llu, spilled intervals %zu; "
                    "max intervals on a ray %zu; differing rays: mirror %zu, download %zu; invariant violations %zu\n",
                    n, done, batches, 1e6 * cpu_s / done, 1e6 * gpu_s / done, (unsigned long long)st.dispatches,
                    (unsigned long long)st.ray_tiles, (unsigned long long)st.retried_rays, (unsigned long long)st.compactions,
                    static_cast<std::size_t>(sculptor.slabs().spilled_intervals()), max_intervals, bad_rays, bad_full, invariant_bad);
        EXPECT_EQ(done, kGpuSegments);
        EXPECT_EQ(bad_rays, 0u);
        EXPECT_EQ(bad_full, 0u);
        EXPECT_EQ(invariant_bad, 0u);
        EXPECT_EQ(st.sweeps, done);
        EXPECT_GT(st.compactions, 0u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
