// Smoke test of `tridex bench --shared` (bench/bench_shared): a short run at two delays times every kind of cut, ends
// with equal models at both sites, and the joiner's own cut waits at least the round trip; a late join after a
// minute replays its 60,000 samples; the flood run over ENet ticks the haptic loop in both phases, floods and refuses
// in the second, and ends with equal models.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bench/bench_shared.hpp"
#include "core/error.hpp"

namespace tridex::bench {
namespace {

TEST(BenchShared, AShortRunTimesEveryCutAndEndsWithEqualModels) {
    SharedBenchOptions o;
    o.delays_ms = {0.0, 40.0};
    o.stroke_s = 0.4;
    o.resolution = 48;
    o.out = (std::filesystem::temp_directory_path() / ("tridex_test_bench_shared_" + std::to_string(::getpid()))).string();
    std::filesystem::remove_all(o.out);
    const std::vector<SharedBenchRow> rows = run_shared_bench(o);
    ASSERT_EQ(rows.size(), 2u);
    for (const SharedBenchRow& r : rows) {
        EXPECT_TRUE(r.digests_equal) << r.delay_ms;
        EXPECT_GT(r.own_host.count(), 0u);
        EXPECT_GT(r.own_join.count(), 0u);
        EXPECT_GT(r.other_at_host.count(), 0u);
        EXPECT_GT(r.other_at_join.count(), 0u);
        EXPECT_GT(r.host_out_bps, 0.0);
        EXPECT_GT(r.join_out_bps, 0.0);
    }
    EXPECT_GE(rows[1].own_join.percentile_ms(0.5), 80.0);      // two ways of 40 ms
    EXPECT_GE(rows[1].other_at_join.percentile_ms(0.5), 40.0);  // one way
    std::ifstream f(std::filesystem::path(o.out) / "shared_bench.json");
    ASSERT_TRUE(f.good());
    EXPECT_EQ(nlohmann::json::parse(f).at("rows").size(), 2u);
    std::filesystem::remove_all(o.out);

    o.join_minutes = {1.0};
    const std::vector<LateJoinRow> late = run_late_join_bench(o);
    ASSERT_EQ(late.size(), 1u);
    EXPECT_EQ(late[0].samples, 60000u);
    EXPECT_GT(late[0].bytes, 100000u);
    EXPECT_LT(late[0].bytes, 60000u * 120u);  // packed: less than the samples' 120 bytes each
    EXPECT_GT(late[0].replay_s, 0.0);
    o.join_minutes = {61.0};
    EXPECT_THROW(run_late_join_bench(o), Error);

    o.loss = 0.7;
    EXPECT_THROW(run_shared_bench(o), Error);
}

TEST(BenchShared, TheFloodRunTicksFloodsRefusesAndEndsWithEqualModels) {
    SharedBenchOptions o;
    o.flood_s = 1.0;
    o.resolution = 48;
    o.out = (std::filesystem::temp_directory_path() / ("tridex_test_bench_flood_" + std::to_string(::getpid()))).string();
    std::filesystem::remove_all(o.out);
    const std::vector<SharedFloodRow> rows = run_shared_flood_bench(o);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].phase, "quiet");
    EXPECT_EQ(rows[1].phase, "flood");
    for (const SharedFloodRow& r : rows) {
        EXPECT_GT(r.ticks, 0u) << r.phase;
        EXPECT_TRUE(r.digests_equal) << r.phase;
        EXPECT_TRUE(r.carved) << r.phase;
    }
    EXPECT_EQ(rows[0].flooded, 0u);
    EXPECT_GT(rows[1].flooded, 0u);
    EXPECT_GT(rows[1].hub_foreign + rows[1].sealed_refused, 0u);
    std::ifstream f(std::filesystem::path(o.out) / "shared_flood.json");
    ASSERT_TRUE(f.good());
    EXPECT_EQ(nlohmann::json::parse(f).at("rows").size(), 2u);
    std::filesystem::remove_all(o.out);

    o.flood_s = 0.0;
    EXPECT_TRUE(run_shared_flood_bench(o).empty());
    o.flood_s = 0.2;
    EXPECT_THROW(run_shared_flood_bench(o), Error);
}

}  // namespace
}  // namespace tridex::bench
