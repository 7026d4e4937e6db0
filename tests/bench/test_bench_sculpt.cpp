// Smoke test of `tridex bench --sculpt` (bench/bench_sculpt): a tiny run writes sculpt_bench.json with the four
// paths, sane (positive, finite) numbers and the memory record, and all paths end with identical models.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sched.h>
#include <set>
#include <string>

#include "bench/bench_sculpt.hpp"
#include "core/error.hpp"

namespace tridex::bench {
namespace {

TEST(BenchSculpt, TinyRunWritesFourPathsWithSaneNumbersAndIdenticalModels) {
    SculptBenchOptions o;
    o.resolutions = {32};
    o.radii_cells = {2.0};
    o.batch = 16;
    o.max_segments = 40;     // all paths carve the whole stroke: 40 segments (16 + 16 + 8 when batched)
    o.min_boolean_s = 1e9;
    o.max_row_s = 1e9;
    o.out = (std::filesystem::temp_directory_path() / "tridex_test_bench_sculpt").string();
    std::filesystem::remove_all(o.out);
    const std::vector<SculptBenchRow> rows = run_sculpt_bench(o);
    ASSERT_EQ(rows.size(), 4u);  // the test environment has lavapipe

    std::ifstream f(std::filesystem::path(o.out) / "sculpt_bench.json");
    ASSERT_TRUE(f.good());
    const nlohmann::json jr = nlohmann::json::parse(f);
    ASSERT_TRUE(jr.is_array());
    std::ifstream fs(std::filesystem::path(o.out) / "sculpt_bench_setup.json");
    ASSERT_TRUE(fs.good());
    const nlohmann::json j = nlohmann::json::parse(fs);
    ASSERT_EQ(jr.size(), 4u);
    std::set<std::string> paths, hashes;
    for (std::size_t i = 0; i < jr.size(); ++i) {
        const nlohmann::json& r = jr[i];
        for (const char* key : {"n", "radius_cells", "path", "segments_per_s", "rays_per_s", "tiles_contoured_per_s",
                                "latency_ms", "rays_per_segment", "step_ms_median", "step_cpu_ms", "contour", "segments", "model_hash"})
            ASSERT_TRUE(r.contains(key)) << "row " << i << " lacks " << key;
        EXPECT_EQ(r["n"].get<int>(), 32);
        EXPECT_EQ(r["radius_cells"].get<double>(), 2.0);
        EXPECT_EQ(r["contour"].get<std::string>(), "cpu");
        EXPECT_EQ(r["segments"].get<int>(), 40);
        for (const char* key : {"segments_per_s", "rays_per_s", "tiles_contoured_per_s", "latency_ms", "rays_per_segment",
                                "step_ms_median", "step_cpu_ms"}) {
            const double v = r[key].get<double>();
            EXPECT_TRUE(std::isfinite(v) && v > 0.0) << "row " << i << " " << key << " = " << v;
        }
        EXPECT_GE(r["latency_ms"].get<double>(), r["step_ms_median"].get<double>());
        // A ball of radius 2 cells: a few dozen rays per set.
        EXPECT_GT(r["rays_per_segment"].get<double>(), 30.0);
        EXPECT_LT(r["rays_per_segment"].get<double>(), 400.0);
        paths.insert(r["path"].get<std::string>());
        hashes.insert(r["model_hash"].get<std::string>());
    }
    EXPECT_EQ(paths, (std::set<std::string>{"cpu-1t", "cpu", "gpu", "gpu-batched"}));
    EXPECT_EQ(hashes.size(), 1u) << "the four paths must end with identical models";
    EXPECT_EQ(rows[0].steps, 40u);  // cpu-1t: one segment per step
    EXPECT_EQ(rows[1].steps, 3u);   // cpu: batches of 16

    // lavapipe on a machine with at least 2 usable cores: the Context pinned the driver's workers.
    ASSERT_TRUE(j.contains("gpu_driver_threads_pinned"));
    cpu_set_t usable;
    CPU_ZERO(&usable);
    ASSERT_EQ(sched_getaffinity(0, sizeof usable, &usable), 0);
    if (CPU_COUNT(&usable) >= 2)
        EXPECT_GT(j["gpu_driver_threads_pinned"].get<int>(), 0);
    else
        EXPECT_EQ(j["gpu_driver_threads_pinned"].get<int>(), 0);
    ASSERT_TRUE(j.contains("memory"));
    const nlohmann::json& mem = j["memory"];
    ASSERT_EQ(mem["gpu_slabs"].size(), 1u);
    EXPECT_GT(mem["gpu_slabs"][0]["bytes_for_pool0"]["total"].get<double>(), 0.0);
    EXPECT_GT(mem["gpu_slabs"][0]["bytes_after_run"]["total"].get<double>(), 0.0);
    EXPECT_TRUE(mem["interval_storage_n1024"]["fits"].get<bool>());
}

TEST(BenchSculpt, ParallelRatiosCompareTheSameFirstSegments) {
    SculptBenchRow one, batched;
    one.batch = 1;
    one.step_s = {1.0, 2.0, 3.0, 4.0, 5.0};
    one.segments = 5;
    batched.batch = 2;
    batched.step_s = {10.0, 20.0, 30.0};
    batched.segments = 6;
    EXPECT_EQ(seconds_for_segments(one, 0), 0.0);
    EXPECT_EQ(seconds_for_segments(one, 3), 6.0);
    EXPECT_EQ(seconds_for_segments(batched, 4), 30.0);  // two calls of two segments
    EXPECT_EQ(seconds_for_segments(batched, 3), 30.0);  // a started call counts whole
    EXPECT_EQ(seconds_for_segments(one, 99), 15.0);     // no more than the row carved
}

TEST(BenchSculpt, RefusesBadOptions) {
    SculptBenchOptions o;
    o.out = (std::filesystem::temp_directory_path() / "tridex_test_bench_sculpt_bad").string();
    o.resolutions = {8};
    EXPECT_THROW(run_sculpt_bench(o), Error);
    o.resolutions = {64};
    o.radii_cells = {0.0};
    EXPECT_THROW(run_sculpt_bench(o), Error);
    o.radii_cells = {2.0};
    o.batch = 0;
    EXPECT_THROW(run_sculpt_bench(o), Error);
    o.batch = 16;
    o.paths = {};
    EXPECT_THROW(run_sculpt_bench(o), Error);
    o.paths = {"cpu", "gpu-fast"};
    EXPECT_THROW(run_sculpt_bench(o), Error);
    o.paths = {"cpu", "gpu-batched", "cpu"};
    EXPECT_THROW(run_sculpt_bench(o), Error);
}

TEST(BenchSculpt, RunsOnlyTheChosenPathsResolutionsAndRadii) {
    SculptBenchOptions o;
    o.resolutions = {32, 40};
    o.radii_cells = {1.5, 3.0};
    o.paths = {"gpu-batched", "cpu"};  // rows come in the bench's own order
    o.batch = 8;
    o.max_segments = 12;
    o.min_boolean_s = 1e9;
    o.max_row_s = 1e9;
    o.out = (std::filesystem::temp_directory_path() / "tridex_test_bench_sculpt_paths").string();
    std::filesystem::remove_all(o.out);
    const std::vector<SculptBenchRow> rows = run_sculpt_bench(o);
    ASSERT_EQ(rows.size(), 8u);  // 2 N x 2 radii x 2 paths; the test environment has lavapipe
    for (std::size_t i = 0; i < rows.size(); i += 2) {
        EXPECT_EQ(rows[i].path, "cpu");
        EXPECT_EQ(rows[i + 1].path, "gpu-batched");
        EXPECT_EQ(rows[i].n, rows[i + 1].n);
        EXPECT_EQ(rows[i].radius_cells, rows[i + 1].radius_cells);
        EXPECT_EQ(rows[i].segments, 12u);
        EXPECT_EQ(rows[i].model_hash, rows[i + 1].model_hash) << "N " << rows[i].n << " r " << rows[i].radius_cells;
    }
    EXPECT_EQ(rows[0].n, 32);
    EXPECT_EQ(rows[0].radius_cells, 1.5);
    EXPECT_EQ(rows[2].radius_cells, 3.0);
    EXPECT_EQ(rows[4].n, 40);
}

}  // namespace
TEST(BenchSculpt, ClayPathsRunTheSameStrokeAsPushAndSmooth) {
    SculptBenchOptions o;
    o.resolutions = {32};
    o.radii_cells = {3.0};
    o.paths = {"clay-smooth", "cpu-1t", "clay-push"};  // rows come in the bench's own order
    o.max_segments = 10;
    o.batch = 4;
    o.min_boolean_s = 1e9;
    o.max_row_s = 1e9;
    o.gpu = false;
    o.out = (std::filesystem::temp_directory_path() / "tridex_test_bench_sculpt_clay").string();
    std::filesystem::remove_all(o.out);
    const std::vector<SculptBenchRow> rows = run_sculpt_bench(o);
    ASSERT_EQ(rows.size(), 3u);
    EXPECT_EQ(rows[0].path, "cpu-1t");
    EXPECT_EQ(rows[1].path, "clay-push");
    EXPECT_EQ(rows[2].path, "clay-smooth");
    for (const SculptBenchRow& r : rows) {
        EXPECT_EQ(r.segments, 10u) << r.path;
        EXPECT_EQ(r.steps, r.path == "cpu-1t" ? 10u : 3u) << r.path;  // cpu-1t: one segment per step; clay: batches
        EXPECT_TRUE(std::isfinite(r.step_ms_median) && r.step_ms_median > 0.0) << r.path;
    }
    // Three different operations on the same stroke: three different models.
    EXPECT_NE(rows[0].model_hash, rows[1].model_hash);
    EXPECT_NE(rows[1].model_hash, rows[2].model_hash);
    EXPECT_NE(rows[0].model_hash, rows[2].model_hash);
}

TEST(BenchSculpt, GpuClayPathsGiveTheCpuClayModels) {
    SculptBenchOptions o;
    o.resolutions = {32};
    o.radii_cells = {3.0};
    o.paths = {"gpu-clay-smooth", "clay-push", "gpu-clay-push", "clay-smooth"};
    o.max_segments = 10;
    o.min_boolean_s = 1e9;
    o.max_row_s = 1e9;
    o.out = (std::filesystem::temp_directory_path() / "tridex_test_bench_sculpt_gpu_clay").string();
    std::filesystem::remove_all(o.out);
    const std::vector<SculptBenchRow> rows = run_sculpt_bench(o);
    if (rows.size() == 2u) GTEST_SKIP() << "no Vulkan device: only the CPU clay rows ran";
    ASSERT_EQ(rows.size(), 4u);
    EXPECT_EQ(rows[0].path, "clay-push");
    EXPECT_EQ(rows[1].path, "clay-smooth");
    EXPECT_EQ(rows[2].path, "gpu-clay-push");
    EXPECT_EQ(rows[3].path, "gpu-clay-smooth");
    for (const SculptBenchRow& r : rows) {
        EXPECT_EQ(r.segments, 10u) << r.path;
        EXPECT_TRUE(std::isfinite(r.step_ms_median) && r.step_ms_median > 0.0) << r.path;
    }
    EXPECT_EQ(rows[0].model_hash, rows[2].model_hash);  // the GPU kernel gives the CPU reference's model
    EXPECT_EQ(rows[1].model_hash, rows[3].model_hash);
    EXPECT_NE(rows[0].model_hash, rows[1].model_hash);
}

}  // namespace tridex::bench
