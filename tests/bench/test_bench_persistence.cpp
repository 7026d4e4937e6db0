// Smoke test of `tridex bench --persistence` (bench/bench_persistence): a tiny run carves, saves and loads the
// model, writes persistence_bench.json with sane numbers, and the loaded model equals the saved one.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bench/bench_persistence.hpp"

namespace tridex::bench {
namespace {

TEST(BenchPersistence, TinyRunWritesRowsWithSaneNumbersAndIdenticalModels) {
    PersistenceBenchOptions o;
    o.resolutions = {32, 48};
    o.out = (std::filesystem::temp_directory_path() / ("tridex_test_bench_persistence_" + std::to_string(::getpid()))).string();
    std::filesystem::remove_all(o.out);
    const std::vector<PersistenceBenchRow> rows = run_persistence_bench(o);
    ASSERT_EQ(rows.size(), 2u);
    for (const PersistenceBenchRow& r : rows) {
        EXPECT_TRUE(r.identical) << r.n;
        EXPECT_GT(r.segments, 3u);
        EXPECT_GT(r.removed_m3, 0.0);  // the stroke carved
        EXPECT_GT(r.file_bytes, 0u);
        EXPECT_GT(r.memory_bytes, r.file_bytes);
        EXPECT_TRUE(std::isfinite(r.save_s) && r.save_s > 0.0);
        EXPECT_TRUE(std::isfinite(r.load_s) && r.load_s > 0.0);
        EXPECT_DOUBLE_EQ(r.ratio, double(r.file_bytes) / double(r.memory_bytes));
    }
    std::ifstream f(std::filesystem::path(o.out) / "persistence_bench.json");
    ASSERT_TRUE(f.good());
    const nlohmann::json j = nlohmann::json::parse(f);
    ASSERT_EQ(j.at("rows").size(), 2u);
    EXPECT_EQ(j["rows"][1]["n"], 48);
    EXPECT_TRUE(j["rows"][0]["identical"].get<bool>());
    EXPECT_TRUE(j.at("setup").contains("zstd_level"));
    std::filesystem::remove_all(o.out);
}

}  // namespace
}  // namespace tridex::bench
