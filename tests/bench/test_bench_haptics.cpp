// Smoke test of `tridex bench --haptics` (bench/bench_haptics): a small run writes haptics_bench.json with one
// row per (N, points), finite positive timings, and a walk that touches the surface the same way at every
// resolution (the contact share may differ only by discretisation); bad options are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bench/bench_haptics.hpp"
#include "core/error.hpp"

namespace tridex::bench {
namespace {

TEST(BenchHaptics, SmallRunTouchesAlikeAtEveryResolutionAndWritesRows) {
    HapticsBenchOptions o;
    o.resolutions = {64, 128};
    o.points = {1, 2, 16};
    o.ticks = 3000;
    o.out = (std::filesystem::temp_directory_path() / "tridex_test_bench_haptics").string();
    std::filesystem::remove_all(o.out);
    const std::vector<HapticsBenchRow> rows = run_haptics_bench(o);
    ASSERT_EQ(rows.size(), 6u);
    for (const HapticsBenchRow& r : rows) {
        EXPECT_TRUE(std::isfinite(r.median_us) && r.median_us > 0.0) << r.n << " " << r.points;
        EXPECT_GE(r.p99_us, r.median_us);
        EXPECT_GE(r.max_us, r.p99_us);
        EXPECT_GE(r.stride, 1);
        // Every tool presses into the surface for most of the walk (the wand's bottom tip lifts off at the
        // ends of its swing).
        EXPECT_GT(r.contact_fraction, r.points == 2 ? 0.4 : 0.8) << "N " << r.n << " points " << r.points;
    }
    for (int i = 0; i < 3; ++i)  // same tool at N = 64 and 128
        EXPECT_NEAR(rows[i].contact_fraction, rows[3 + i].contact_fraction, 0.1) << "points " << rows[i].points;

    std::ifstream f(std::filesystem::path(o.out) / "haptics_bench.json");
    ASSERT_TRUE(f.good());
    const nlohmann::json j = nlohmann::json::parse(f);
    ASSERT_TRUE(j.is_array());
    ASSERT_EQ(j.size(), 6u);
    for (const nlohmann::json& r : j)
        for (const char* k : {"n", "points", "median_us", "p99_us", "max_us"}) EXPECT_TRUE(r.contains(k)) << k;
}

TEST(BenchHaptics, RefusesBadOptions) {
    HapticsBenchOptions o;
    o.out = (std::filesystem::temp_directory_path() / "tridex_test_bench_haptics_bad").string();
    o.resolutions = {8};
    EXPECT_THROW(run_haptics_bench(o), Error);
    o.resolutions = {64};
    o.points = {0};
    EXPECT_THROW(run_haptics_bench(o), Error);
    o.points = {65};
    EXPECT_THROW(run_haptics_bench(o), Error);
    o.points = {1};
    o.ticks = 0;
    EXPECT_THROW(run_haptics_bench(o), Error);
    o.ticks = 1000;
    o.resolutions.clear();
    EXPECT_THROW(run_haptics_bench(o), Error);
}

}  // namespace
}  // namespace tridex::bench
