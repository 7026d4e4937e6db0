// Sweep spacing (compute/tools/site_sweeps.hpp): which samples a large tool leaves unswept, that a stroke still ends
// where the tool did, how far the spaced sweeps' volume lies from sweeping every sample (within the sagitta of the
// path over one spacing), and that the sculpt thread and a journal replay in any batches give the same dexels.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <vector>

#include "journal_stream.hpp"
#include "journalled_session.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/tools/site_sweeps.hpp"
#include "compute/tools/symmetry.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

constexpr int kCells = 280;  // 0.1 m box: 0.357 mm cells, so a 6 mm ball is 16.8 cells in radius

ToolSample ball(const Vec3& p, ToolOp op = ToolOp::kSubtract, double radius_m = 0.006) {
    ToolSample s;
    s.position = p;
    s.tool.radius_m = radius_m;
    s.op = op;
    s.material = 3;
    return s;
}

// Three strokes (subtract, union, paint), `per` samples each 1 ms apart along a wavy path across the box's +z face,
// slow enough that several samples fall within one spacing (0.6 mm), with a pause (op none) between strokes.
std::vector<ToolSample> slow_stream(int per) {
    std::vector<ToolSample> out;
    const ToolOp ops[] = {ToolOp::kSubtract, ToolOp::kUnion, ToolOp::kPaint};
    for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < per; ++i) {
            const double u = i / static_cast<double>(per - 1);
            ToolSample s = ball(Vec3(-0.04 + 0.08 * u, 0.015 * std::sin(6.0 * u) + 0.012 * k, 0.047 - 0.003 * std::sin(4.0 * u)),
                                ops[k]);
            s.t_s = static_cast<double>(out.size()) * 1e-3;
            out.push_back(s);
        }
        ToolSample lift = out.back();
        lift.op = ToolOp::kNone;
        lift.position.z += 0.02;
        lift.t_s = static_cast<double>(out.size()) * 1e-3;
        out.push_back(lift);
    }
    return out;
}

TEST(SweepSpacing, WhichSamplesMayBeLeftUnswept) {
    const double cell = 0.1 / kCells;
    const ToolSample a = ball(Vec3(0.0));
    EXPECT_TRUE(compute::within_sweep_spacing(a, ball(Vec3(0.0005, 0.0, 0.0)), cell));   // 0.5 mm < 0.6 mm
    EXPECT_FALSE(compute::within_sweep_spacing(a, ball(Vec3(0.0007, 0.0, 0.0)), cell));  // past the spacing
    EXPECT_FALSE(compute::within_sweep_spacing(a, ball(Vec3(0.0001, 0.0, 0.0)), 0.1 / 200));  // 12 cells: too small
    EXPECT_FALSE(compute::within_sweep_spacing(a, ball(Vec3(0.0001, 0.0, 0.0)), 0.0));
    EXPECT_FALSE(compute::within_sweep_spacing(a, ball(Vec3(0.0001, 0.0, 0.0), ToolOp::kUnion), cell));  // op changed
    EXPECT_FALSE(compute::within_sweep_spacing(a, ball(Vec3(0.0001, 0.0, 0.0), ToolOp::kPush), cell));
    EXPECT_FALSE(compute::within_sweep_spacing(ball(Vec3(0.0), ToolOp::kNone), ball(Vec3(0.0001, 0.0, 0.0)), cell));
    EXPECT_FALSE(compute::within_sweep_spacing(a, ball(Vec3(0.0001, 0.0, 0.0), ToolOp::kSubtract, 0.0061), cell));
    // A flat end: only at the anchor's orientation (a ball's orientation does not change what it sweeps).
    ToolSample f = a, g = ball(Vec3(0.0001, 0.0, 0.0));
    f.tool.kind = g.tool.kind = ToolKind::kFlatEnd;
    f.tool.length_m = g.tool.length_m = 0.02;
    EXPECT_TRUE(compute::within_sweep_spacing(f, g, cell));
    g.orientation = glm::angleAxis(0.01, Vec3(1.0, 0.0, 0.0));
    EXPECT_FALSE(compute::within_sweep_spacing(f, g, cell));
    ToolSample b = ball(Vec3(0.0001, 0.0, 0.0));
    b.orientation = g.orientation;
    EXPECT_TRUE(compute::within_sweep_spacing(a, b, cell));
}

// Applies `samples` as one stroke through SiteSweeps with `cell_m` (0: every sample swept), then the stroke's close.
std::size_t sweep_stroke(compute::TriDexel& m, const std::vector<ToolSample>& samples, double cell_m) {
    compute::SiteSweeps sites;
    std::vector<compute::Sweep> sweeps;
    const Vec3 centre = compute::symmetry_centre(m.lattice);
    for (const ToolSample& s : samples) sites.advance(s, nullptr, nullptr, centre, cell_m, sweeps);
    sites.finish_strokes(centre, sweeps);
    for (const compute::Sweep& w : sweeps) compute::apply_sweep(m, w);
    return sweeps.size();
}

TEST(SweepSpacing, ASpacedStrokeEndsWhereTheToolDidAndCutsWithinTheSagitta) {
    std::vector<ToolSample> cut;
    for (int i = 0; i < 800; ++i) {  // 0.05 mm a sample along an arc of radius 30 mm, ending at rest
        const double a = 0.8 * i / 799.0;
        cut.push_back(ball(Vec3(0.03 * std::sin(a) - 0.012, 0.03 * (1.0 - std::cos(a)) - 0.01, 0.047)));
    }
    compute::TriDexel every = test::box_model(kCells), spaced = test::box_model(kCells);
    const std::size_t n_every = sweep_stroke(every, cut, 0.0);
    const std::size_t n_spaced = sweep_stroke(spaced, cut, every.lattice.cell_m);
    EXPECT_EQ(n_every, 799u);
    EXPECT_LT(n_spaced, n_every / 8) << "0.6 mm spacing over 0.05 mm steps";
    EXPECT_GT(n_spaced, 30u);
    // The material differs by at most the sagitta of a 0.6 mm chord of the 30 mm arc (1.5e-6 m) over the path's side
    // (its length times the ball's diameter), twice for both walls: the z rays' lengths summed, in m^3.
    const double sagitta = 0.0006 * 0.0006 / (8.0 * 0.03);
    const double cell = every.lattice.cell_m;
    const compute::RaySet& a = every.sets[2];
    const compute::RaySet& b = spaced.sets[2];
    double diff_m3 = 0.0, removed_m3 = 0.0;
    const compute::TriDexel box = test::box_model(kCells);
    for (std::size_t r = 0; r < a.rays.size(); ++r) {
        double la = 0.0, lb = 0.0, l0 = 0.0;
        for (const compute::Interval& iv : a.rays[r]) la += iv.exit - iv.enter;
        for (const compute::Interval& iv : b.rays[r]) lb += iv.exit - iv.enter;
        for (const compute::Interval& iv : box.sets[2].rays[r]) l0 += iv.exit - iv.enter;
        diff_m3 += std::abs(la - lb) * cell * cell * cell;
        removed_m3 += (l0 - la) * cell * cell * cell;
    }
    const double bound_m3 = 2.0 * sagitta * (0.03 * 0.8) * 0.012;
    std::printf("[sweep spacing] %zu sweeps for 800 samples (every sample: %zu); material differs by %.3g m^3 of %.3g "
                "m^3 removed (bound %.3g m^3)\n",
                n_spaced, n_every, diff_m3, removed_m3, bound_m3);
    EXPECT_GT(removed_m3, 1e-6);
    EXPECT_LE(diff_m3, bound_m3);
    // The stroke ends where the tool did: the ray under its last sample is cut alike (to float rounding).
    const Vec3 g = every.lattice.to_grid(cut.back().position);
    const std::size_t under = static_cast<std::size_t>(std::lround(g.x)) +
                              static_cast<std::size_t>(a.nu) * static_cast<std::size_t>(std::lround(g.y));
    ASSERT_EQ(a.rays[under].size(), b.rays[under].size());
    for (std::size_t k = 0; k < a.rays[under].size(); ++k) {
        EXPECT_NEAR(a.rays[under][k].enter, b.rays[under][k].enter, 1e-3);
        EXPECT_NEAR(a.rays[under][k].exit, b.rays[under][k].exit, 1e-3);
    }
}

TEST(SweepSpacing, TheSculptThreadAndItsJournalInAnyBatchesGiveTheSameDexels) {
    const std::string path =
        (fs::temp_directory_path() / ("tridex_sweep_spacing_" + std::to_string(::getpid()) + ".tdj")).string();
    const std::vector<ToolSample> samples = slow_stream(600);
    compute::TriDexel live = test::box_model(kCells);
    const test::JournalledRun run = test::sculpt_journalled(live, samples, path);
    EXPECT_EQ(run.journal.error, "");
    EXPECT_LT(run.sculpt.booleans, samples.size() / 3) << "the slow strokes' samples were spaced";
    EXPECT_GT(run.sculpt.booleans, 50u);
    const compute::Journal j = compute::read_journal(path);
    compute::TriDexel again = test::box_model(kCells), split = test::box_model(kCells);
    compute::journal_apply(again, j.records);
    std::vector<compute::JournalRecord> singles;  // one sample a batch, the marks where they were
    for (const compute::JournalRecord& r : j.records) {
        if (r.kind != compute::JournalKind::kBatch) {
            singles.push_back(r);
            continue;
        }
        for (const ToolSample& s : r.samples) {
            compute::JournalRecord one = r;
            one.samples.assign(1, s);
            singles.push_back(one);
        }
    }
    for (std::size_t k = 0; k < singles.size(); ++k) singles[k].index = k;
    compute::journal_apply(split, singles);
    EXPECT_EQ(compute::model_digest(again), compute::model_digest(live));
    EXPECT_EQ(compute::model_digest(split), compute::model_digest(live));
    fs::remove(path);
}

}  // namespace
}  // namespace tridex::app
