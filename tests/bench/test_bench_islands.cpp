// Smoke test of `tridex bench --islands` (bench/bench_islands): a small run carves the deep cut across the bunny,
// removes its specks at the stroke's end (one mesh part left) and writes islands_bench.json with sane numbers.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bench/bench_islands.hpp"
#include "core/error.hpp"

namespace tridex::bench {
namespace {

TEST(BenchIslands, SmallRunRemovesTheSpecksOfTheDeepCut) {
    IslandBenchOptions o;
    o.resolutions = {128};
    o.repeats = 2;
    o.out = (std::filesystem::temp_directory_path() / ("tridex_test_bench_islands_" + std::to_string(::getpid()))).string();
    std::filesystem::remove_all(o.out);
    const std::vector<IslandBenchRow> rows = run_islands_bench(o);
    ASSERT_EQ(rows.size(), 1u);
    const IslandBenchRow& r = rows[0];
    EXPECT_GT(r.sweeps, 100u);
    EXPECT_GT(r.nodes, 0u);
    EXPECT_LE(r.nodes, r.box_nodes);
    EXPECT_EQ(r.parts_before, r.specks + 1);  // each speck was one part of the mesh
    EXPECT_EQ(r.parts_after, 1u);
    EXPECT_GE(r.search_max_ms, r.search_median_ms);
    std::ifstream f(std::filesystem::path(o.out) / "islands_bench.json");
    ASSERT_TRUE(f.good());
    const nlohmann::json j = nlohmann::json::parse(f);
    ASSERT_EQ(j.at("rows").size(), 1u);
    EXPECT_EQ(j["rows"][0]["mesh_parts_after"], 1);
    std::filesystem::remove_all(o.out);

    o.resolutions = {8};
    EXPECT_THROW(run_islands_bench(o), Error);
}

}  // namespace
}  // namespace tridex::bench
