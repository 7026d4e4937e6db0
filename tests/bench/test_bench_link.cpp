// `tridex bench --link` and `--filter` on small runs: the link target (at 10 ms, local rendering's penetration at
// most a third of distributed's and stable where distributed is not), rows and files written; the filter trades
// chatter for lag.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bench/bench_filter.hpp"
#include "bench/bench_link.hpp"
#include "core/error.hpp"

namespace tridex::bench {
namespace {

TEST(BenchLink, LocalRenderingHoldsTheWallWhereDistributedDoesNot) {
    LinkBenchOptions o;
    o.latencies_ms = {0.0, 10.0};
    o.losses = {0.0};
    o.out = (std::filesystem::temp_directory_path() / "tridex_test_bench_link").string();
    std::filesystem::remove_all(o.out);
    const std::vector<LinkBenchRow> rows = run_link_bench(o);
    ASSERT_EQ(rows.size(), 4u);
    const LinkBenchRow &d0 = rows[0], &d10 = rows[1], &l0 = rows[2], &l10 = rows[3];
    EXPECT_EQ(d10.mode, "distributed");
    EXPECT_EQ(l10.mode, "local");
    EXPECT_TRUE(d0.stable);
    EXPECT_TRUE(l0.stable);
    EXPECT_EQ(d0.force_rms_error_n, 0.0);
    EXPECT_FALSE(d10.stable);
    EXPECT_TRUE(l10.stable);
    EXPECT_LE(l10.max_penetration_m, d10.max_penetration_m / 3.0);
    EXPECT_GT(d10.rtt_median_us, 20000.0 - 1.0);
    EXPECT_GT(l10.rate_hz, 900.0);
    std::ifstream f(std::filesystem::path(o.out) / "link_bench.json");
    ASSERT_TRUE(f.good());
    const nlohmann::json j = nlohmann::json::parse(f);
    ASSERT_EQ(j.size(), 4u);
    for (const char* k : {"mode", "latency_ms", "loss", "rate_hz", "max_penetration_m", "force_rms_error_n",
                          "passivity_energy_j", "stable"})
        EXPECT_TRUE(j[1].contains(k)) << k;
    o.losses = {0.9};
    EXPECT_THROW(run_link_bench(o), Error);
}

TEST(BenchFilter, MoreFilteringLessChatterMoreLag) {
    FilterBenchOptions o;
    o.alphas = {0.0, 0.9};
    o.out = (std::filesystem::temp_directory_path() / "tridex_test_bench_filter").string();
    std::filesystem::remove_all(o.out);
    const std::vector<FilterBenchRow> rows = run_filter_bench(o);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_GT(rows[0].chatter_n, 0.0) << "quantisation and noise must make the force chatter";
    EXPECT_LT(rows[1].chatter_n, 0.5 * rows[0].chatter_n);
    EXPECT_LT(rows[0].lag_ms, 1.0);
    EXPECT_GT(rows[1].lag_ms, 4.0);
    EXPECT_NEAR(rows[1].lag_theory_ms, 9.0, 1e-9);
    EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(o.out) / "filter_bench.json"));
    o.alphas = {1.0};
    EXPECT_THROW(run_filter_bench(o), Error);
}

}  // namespace
}  // namespace tridex::bench
