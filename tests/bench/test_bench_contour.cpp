// Smoke test of `tridex bench --contour` (bench/bench_contour): a small run times the three ways of marking what to
// re-contour, gives the same mesh with each, and visits fewer cells with partial tiles and fewer still with the
// changed ends; contour_bench.json holds the rows.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bench/bench_contour.hpp"
#include "core/error.hpp"

namespace tridex::bench {
namespace {

TEST(BenchContour, SmallRunGivesTheSameMeshAndVisitsFewerCells) {
    ContourBenchOptions o;
    o.resolutions = {64};
    o.out =
        (std::filesystem::temp_directory_path() / ("tridex_test_bench_contour_" + std::to_string(::getpid()))).string();
    std::filesystem::remove_all(o.out);
    const std::vector<ContourBenchRow> rows = run_contour_bench(o);
    ASSERT_EQ(rows.size(), 3u);
    for (const ContourBenchRow& r : rows) {
        EXPECT_EQ(r.n, 64);
        EXPECT_GT(r.steps, 100u);
        EXPECT_EQ(r.idle_steps, 0u) << r.marks;  // every step moves the ball along the groove
        EXPECT_TRUE(r.same_mesh) << r.marks;
        EXPECT_GT(r.tiles_per_step, 0.0) << r.marks;
        EXPECT_GE(r.ms_p99, r.ms_median) << r.marks;
        EXPECT_GT(r.ratio_to_whole, 0.0) << r.marks;
    }
    EXPECT_EQ(rows[0].partial_per_step, 0.0);  // whole tiles
    EXPECT_GT(rows[1].partial_per_step, 0.0);
    EXPECT_LT(rows[1].cells_per_step, rows[0].cells_per_step);
    EXPECT_LT(rows[2].cells_per_step, rows[1].cells_per_step);
    EXPECT_LE(rows[2].tiles_per_step, rows[1].tiles_per_step);
    std::ifstream f(std::filesystem::path(o.out) / "contour_bench.json");
    ASSERT_TRUE(f.good());
    const nlohmann::json j = nlohmann::json::parse(f);
    ASSERT_EQ(j.at("rows").size(), 3u);
    EXPECT_EQ(j["rows"][2]["marks"], "changed ends, partial tiles");
    EXPECT_EQ(j["rows"][2]["same_mesh"], true);
    std::filesystem::remove_all(o.out);

    o.resolutions = {8};
    EXPECT_THROW(run_contour_bench(o), Error);
}

}  // namespace
}  // namespace tridex::bench
