// The progress of long steps (app/support/progress.hpp), driven with a fake clock and a fake output: on a terminal a
// bar redrawn in place, at most every kRedrawS, replaced by the step's time; elsewhere one line per step; a quick step
// prints nothing; steps nest, each with its own line. No real time is measured.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "app/support/progress.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/parallel/task_pool.hpp"
#include "core/primitives.hpp"

namespace tridex::app {
namespace {

// A fake output: what was written, and a clock the test sets.
struct FakeOutput {
    std::string text;
    double now = 100.0;

    ProgressOutput output(bool terminal) {
        ProgressOutput o;
        o.write = [this](std::string_view s) { text += s; };
        o.now_s = [this] { return now; };
        o.terminal = terminal;
        o.columns = 80;
        return o;
    }
};

TEST(Progress, ATerminalGetsABarRedrawnInPlaceAtMostTenTimesASecond) {
    FakeOutput out;
    ProgressReporter r(out.output(true));
    {
        ProgressReporter::Step step = r.step("contouring the workpiece");
        out.now += 0.05;
        step.update(0.10);  // too soon after the start: not drawn
        EXPECT_EQ(out.text, "");
        out.now += 0.15;
        step.update(0.25);
        EXPECT_EQ(out.text, "\rcontouring the workpiece [######..................]  25% 0.2 s\x1b[K");
        out.text.clear();
        for (int i = 0; i < 50; ++i) step.fn()(0.3 + 0.001 * i);  // many updates within the same instant: none drawn
        EXPECT_EQ(out.text, "");
        out.now += 12.3;
        step.update(1.0);
        EXPECT_EQ(out.text, "\rcontouring the workpiece [########################] 100% 12.5 s\x1b[K");
        out.text.clear();
    }
    // The end replaces the bar with the step's time, and ends the line.
    EXPECT_EQ(out.text, "\r\x1b[Kcontouring the workpiece: 12.5 s\n");
}

TEST(Progress, ALongNameGivesWayToTheBarOnANarrowTerminal) {
    FakeOutput out;
    ProgressOutput o = out.output(true);
    o.columns = 60;
    ProgressReporter r(o);
    ProgressReporter::Step step = r.step(std::string(100, 'x'));
    out.now += 0.5;
    step.update(0.5);
    EXPECT_EQ(out.text, "\r" + std::string(18, 'x') + "... [############............]  50% 0.5 s\x1b[K");
    EXPECT_EQ(out.text.size(), std::string("\r").size() + 59 + std::string("\x1b[K").size()) << out.text;
}

TEST(Progress, ElsewhereEachStepIsOneLineWithItsTimeAndNoBar) {
    FakeOutput out;
    ProgressReporter r(out.output(false));
    {
        ProgressReporter::Step step = r.step("scan-converting bunny.off at 2048 cells");
        for (int i = 0; i <= 100; ++i) {
            out.now += 0.1;
            step.update(i / 100.0);
        }
        EXPECT_EQ(out.text, "") << "no bar and no percentage in a log";
    }
    {
        ProgressReporter::Step step = r.step("contouring the workpiece");
        out.now += 3.0;
        step.update(1.0);
    }
    EXPECT_EQ(out.text, "scan-converting bunny.off at 2048 cells: 10.1 s\ncontouring the workpiece: 3.0 s\n");
}

TEST(Progress, AQuickStepPrintsNothingAndItsBarIsErased) {
    FakeOutput log, term;
    ProgressReporter quiet_log(log.output(false));
    ProgressReporter quiet_term(term.output(true));
    {
        ProgressReporter::Step a = quiet_log.step("loading m.tdx");
        ProgressReporter::Step b = quiet_term.step("loading m.tdx");
        log.now += 0.5;
        term.now += 0.5;
        a.update(0.9);
        b.update(0.9);
    }
    EXPECT_EQ(log.text, "");
    ASSERT_FALSE(term.text.empty());
    EXPECT_EQ(term.text.substr(term.text.size() - 4), "\r\x1b[K") << "the bar drawn is erased";
}

TEST(Progress, StepsNestEachWithItsOwnLine) {
    FakeOutput out;
    ProgressReporter r(out.output(true));
    {
        ProgressReporter::Step outer = r.step("bench --render at 512 cells");
        {
            ProgressReporter::Step inner = r.step("scan-converting bunny.off at 512 cells");
            out.now += 2.0;
            outer.update(0.1);  // the outer step's bar waits while the inner one runs
            EXPECT_EQ(out.text, "");
            inner.update(0.5);
            EXPECT_EQ(out.text, "\rscan-converting bunny.off at 512 cells [############............]  50% 2.0 s\x1b[K");
            out.text.clear();
        }
        EXPECT_EQ(out.text, "\r\x1b[Kscan-converting bunny.off at 512 cells: 2.0 s\n");
        out.text.clear();
        out.now += 1.0;
        outer.update(0.75);  // back to the outer step's bar
        EXPECT_EQ(out.text, "\rbench --render at 512 cells [##################......]  75% 3.0 s\x1b[K");
    }
}

TEST(Progress, AStepEndsOnceAndAMovedStepEndsWithItsNewOwner) {
    FakeOutput out;
    ProgressReporter r(out.output(false));
    ProgressReporter::Step a = r.step("writing out.ply");
    out.now += 1.5;
    ProgressReporter::Step b(std::move(a));
    EXPECT_DOUBLE_EQ(b.finish(), 1.5);
    EXPECT_DOUBLE_EQ(b.finish(), 0.0);
    EXPECT_EQ(out.text, "writing out.ply: 1.5 s\n");
}

// Work on the task pool tells its fraction from the calling thread, in order, ending at 1; the chunks are those of
// one pool_for call.
TEST(Progress, PoolWorkTellsItsFractionInOrder) {
    std::vector<double> heard;
    std::vector<int> done(1000, 0);
    compute::pool_for_progress(
        done.size(), 7,
        [&](const compute::Chunk& c) {
            EXPECT_EQ(c.first % 7, 0u) << "a slice split a chunk";
            for (std::size_t i = c.first; i < c.last; ++i) ++done[i];
        },
        [&](double f) { heard.push_back(f); });
    for (int d : done) ASSERT_EQ(d, 1);
    ASSERT_FALSE(heard.empty());
    EXPECT_LE(heard.size(), compute::kProgressSlices);
    for (std::size_t i = 1; i < heard.size(); ++i) EXPECT_GT(heard[i], heard[i - 1]);
    EXPECT_DOUBLE_EQ(heard.back(), 1.0);
}

// Scan conversion and contouring tell their progress, ending at 1, and give the same model and mesh as without.
TEST(Progress, ScanConversionAndContouringTellTheirFractionAndChangeNothing) {
    const TriMesh sphere = icosphere_mesh(Vec3(0.0), 0.05, 3);
    const compute::Lattice lattice = compute::Lattice::around(sphere.bounds(), 64);
    compute::TriDexel quiet = compute::TriDexel::empty(lattice, std::size_t{1} << 30);
    compute::TriDexel told = compute::TriDexel::empty(lattice, std::size_t{1} << 30);
    std::vector<double> scan, contour;
    compute::scan_convert(sphere, quiet);
    compute::scan_convert(sphere, told, [&](double f) { scan.push_back(f); });
    for (int a = 0; a < 3; ++a) {
        ASSERT_EQ(quiet.sets[a].rays.size(), told.sets[a].rays.size());
        for (std::size_t r = 0; r < quiet.sets[a].rays.size(); ++r) {
            const auto& p = quiet.sets[a].rays[r];
            const auto& q = told.sets[a].rays[r];
            ASSERT_EQ(p.size(), q.size());
            for (std::size_t i = 0; i < p.size(); ++i) ASSERT_TRUE(p[i].enter == q[i].enter && p[i].exit == q[i].exit);
        }
    }
    compute::Contourer c_quiet(quiet), c_told(told);
    c_quiet.update(quiet);
    c_told.update(told, [&](double f) { contour.push_back(f); });
    const TriMesh a = c_quiet.mesh(), b = c_told.mesh();
    EXPECT_TRUE(a.positions == b.positions && a.triangles == b.triangles);
    for (const std::vector<double>* heard : {&scan, &contour}) {
        ASSERT_GT(heard->size(), 3u);
        EXPECT_TRUE(std::is_sorted(heard->begin(), heard->end()));
        EXPECT_DOUBLE_EQ(heard->back(), 1.0);
    }
}

}  // namespace
}  // namespace tridex::app
