// Smoke test of `tridex bench --desk` (bench/bench_desk): short offscreen mouse sessions at the desk's size, run
// twice, write a row per run with frames, per-pass GPU times and a measured cursor-to-frame lag, and a row of their
// medians; bad options are refused by name.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bench/bench_desk.hpp"
#include "core/error.hpp"

namespace tridex::bench {
namespace {

namespace fs = std::filesystem;

TEST(BenchDesk, ShortOffscreenSessionReportsFramesPassesAndLag) {
    DeskBenchOptions o;
    o.seconds = 4.0;
    o.stereo = {"mono"};
    o.display = "offscreen";
    o.min_scales = {0.75};
    o.repeats = 2;
    o.out = (fs::temp_directory_path() / ("tridex_test_bench_desk_" + std::to_string(::getpid()))).string();
    fs::remove_all(o.out);
    const std::vector<DeskBenchRow> rows = run_desk_bench(o);
    ASSERT_EQ(rows.size(), 3u);  // two runs and their median
    EXPECT_EQ(rows[0].repeat, 1);
    EXPECT_EQ(rows[1].repeat, 2);
    EXPECT_EQ(rows[2].repeat, 0);
    EXPECT_DOUBLE_EQ(rows[2].frame_median_ms, 0.5 * (rows[0].frame_median_ms + rows[1].frame_median_ms));
    EXPECT_DOUBLE_EQ(rows[2].lag_p99_ms, 0.5 * (rows[0].lag_p99_ms + rows[1].lag_p99_ms));
    const DeskBenchRow& r = rows[0];
    EXPECT_EQ(r.stereo, "mono");
    EXPECT_GT(r.frames, 20u);  // paced at 60 Hz for 4 s
    EXPECT_GT(r.frame_median_ms, 0.0);
    EXPECT_GE(r.frame_p99_ms, r.frame_median_ms);
    EXPECT_GT(r.lag_median_ms, 0.0);  // the scripted cursor moved the tool and a frame drew it there
    EXPECT_GT(r.lag_frames, 0.0);
    EXPECT_TRUE(r.passes.contains("opaque.left")) << r.passes.dump();
    EXPECT_FALSE(r.passes.contains("opaque.right")) << "mono draws one eye";
    EXPECT_EQ(r.min_scale, 0.75);
    EXPECT_EQ(r.frame_budget.at("min_scale"), 1.0) << "offscreen frames are never scaled";
    EXPECT_EQ(r.max_lod_px, 2.0);
    EXPECT_EQ(r.frame_budget.at("coarse_lod_px"), 1.0) << "nor their levels coarsened";
    std::ifstream f(fs::path(o.out) / "desk_bench.json");
    ASSERT_TRUE(f.good());
    const nlohmann::json j = nlohmann::json::parse(f);
    ASSERT_EQ(j.size(), 3u);
    EXPECT_EQ(j[2]["repeat"], 0);
    EXPECT_EQ(j[0]["width"], 960);
    EXPECT_EQ(j[0]["target_median_ms"], 25.0);
    EXPECT_EQ(j[0]["min_render_scale"], 0.75);
    EXPECT_EQ(j[0]["max_lod_px"], 2.0);
    fs::remove_all(o.out);
}

// After a lead-in the cursor carves as without one, and the row's frames are those after it: fewer than the
// session's, which the report counts whole.
TEST(BenchDesk, ARowAfterALeadInTimesOnlyTheFramesAfterIt) {
    DeskBenchOptions o;
    o.seconds = 4.0;
    o.lead_in_s = 2.0;
    o.stereo = {"mono"};
    o.display = "offscreen";
    o.min_scales = {1.0};
    o.out = (fs::temp_directory_path() / ("tridex_test_bench_desk_lead_" + std::to_string(::getpid()))).string();
    fs::remove_all(o.out);
    const std::vector<DeskBenchRow> rows = run_desk_bench(o);
    ASSERT_EQ(rows.size(), 1u);
    const DeskBenchRow& r = rows[0];
    const nlohmann::json report =
        nlohmann::json::parse(std::ifstream(fs::path(o.out) / "desk" / "n0_mono_scale1_run1" / "report.json"));
    const auto whole = report.at("frames").at("count").get<std::uint64_t>();
    EXPECT_GT(r.frames, 10u);  // paced at 60 Hz for 4 s, on a loaded machine fewer
    EXPECT_LT(r.frames, whole);
    EXPECT_GT(whole - r.frames, whole / 8) << "the 2 s lead-in's frames (of about 6 s) are left out";
    EXPECT_GT(r.frame_median_ms, 0.0);
    EXPECT_GE(r.frame_p99_ms, r.frame_median_ms);
    EXPECT_GT(r.lag_median_ms, 0.0);  // the grooves came after the lead-in
    EXPECT_NEAR(report.at("session_s").get<double>(), 6.0, 1.0);
    const nlohmann::json j = nlohmann::json::parse(std::ifstream(fs::path(o.out) / "desk_bench.json"));
    EXPECT_EQ(j[0]["lead_in_s"], 2.0);
    fs::remove_all(o.out);
}

TEST(BenchDesk, RefusesBadOptionsByName) {
    DeskBenchOptions o;
    o.out = (fs::temp_directory_path() / ("tridex_test_bench_desk_bad_" + std::to_string(::getpid()))).string();
    auto refused = [&](const DeskBenchOptions& bad, const std::string& name) {
        try {
            run_desk_bench(bad);
            ADD_FAILURE() << "accepted; expected a refusal naming " << name;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        }
    };
    DeskBenchOptions b = o;
    b.seconds = 1.0;
    refused(b, "--desk-seconds");
    b = o;
    b.width = 10;
    refused(b, "--desk-width");
    b = o;
    b.stereo = {"mono", "quad"};
    refused(b, "--desk-stereo");
    b = o;
    b.display = "wall";
    refused(b, "--desk-display");
    b = o;
    b.min_scales = {1.0, 0.25};
    refused(b, "--desk-scales");
    b = o;
    b.lod_px = 0.5;
    refused(b, "--desk-lod-px");
    b = o;
    b.repeats = 0;
    refused(b, "--desk-repeats");
    b = o;
    b.lead_in_s = -1.0;
    refused(b, "--desk-lead-in");
    EXPECT_FALSE(fs::exists(o.out));
}

}  // namespace
}  // namespace tridex::bench
