// Smoke test of `tridex bench --undo` (bench/bench_undo): a tiny run on the CPU path carves its grooves through a
// real sculpt thread, undoes and redoes every one, and writes undo_bench.json with sane numbers.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bench/bench_undo.hpp"
#include "core/error.hpp"

namespace tridex::bench {
namespace {

TEST(BenchUndo, TinyRunUndoesAndRedoesEveryStroke) {
    UndoBenchOptions o;
    o.resolutions = {48};
    o.paths = {"cpu"};
    o.strokes = 3;
    o.segments = 40;
    o.out = (std::filesystem::temp_directory_path() / ("tridex_test_bench_undo_" + std::to_string(::getpid()))).string();
    std::filesystem::remove_all(o.out);
    const std::vector<UndoBenchRow> rows = run_undo_bench(o);
    ASSERT_EQ(rows.size(), 1u);
    const UndoBenchRow& r = rows[0];
    EXPECT_EQ(r.path, "cpu");
    EXPECT_EQ(r.strokes, 3u);  // every groove became an undo step, and is one again after its redo
    EXPECT_GT(r.rays_median, 0.0);
    EXPECT_GT(r.undo_median_ms, 0.0);
    EXPECT_LE(r.undo_median_ms, r.undo_p95_ms);
    EXPECT_LE(r.undo_p95_ms, r.undo_max_ms);
    EXPECT_GT(r.redo_median_ms, 0.0);
    EXPECT_GT(r.history_bytes_per_stroke, 0.0);
    EXPECT_EQ(r.target_ms, 0.0);  // the 16 ms target is for N = 256
    std::ifstream f(std::filesystem::path(o.out) / "undo_bench.json");
    ASSERT_TRUE(f.good());
    const nlohmann::json j = nlohmann::json::parse(f);
    ASSERT_EQ(j.at("rows").size(), 1u);
    EXPECT_EQ(j["rows"][0]["undo_ms"].size(), 3u);
    EXPECT_EQ(j["rows"][0]["redo_ms"].size(), 3u);
    EXPECT_TRUE(j["rows"][0]["target_met"].is_null());
    std::filesystem::remove_all(o.out);

    o.paths = {"metal"};
    EXPECT_THROW(run_undo_bench(o), Error);
}

}  // namespace
}  // namespace tridex::bench
