// `tridex bench --session` on a tiny run: every row comes from a real session's report and is written to JSON.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "bench/bench_session.hpp"
#include "core/error.hpp"

namespace tridex::bench {
namespace {

TEST(BenchSession, RowsComeFromSessionsAndAreWritten) {
    SessionBenchOptions o;
    o.resolutions = {48};
    o.paths = {"cpu", "gpu"};
    o.seconds = 0.5;
    o.out = (std::filesystem::temp_directory_path() / "tridex_bench_session").string();
    const std::vector<SessionBenchRow> rows = run_session_bench(o);
    ASSERT_EQ(rows.size(), 2u);
    for (const SessionBenchRow& r : rows) {
        EXPECT_EQ(r.n, 48);
        EXPECT_GE(r.ticks, 450u);  // 0.5 s at 1 kHz
        EXPECT_GT(r.period_p50_us, 500.0);
        EXPECT_LT(r.period_p50_us, 2000.0);
        EXPECT_GT(r.booleans, 0u);
        EXPECT_GT(r.volume_removed_m3, 0.0);
    }
    EXPECT_EQ(rows[0].path, "cpu");
    std::ifstream in(std::filesystem::path(o.out) / "session_bench.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    ASSERT_EQ(j.size(), 2u);
    EXPECT_EQ(j[0]["n"], 48);
    // (Live sessions differ run to run: the hand feels the surface the sculpt thread published by then. Only a
    // replay of the same samples is bit-identical, which the replay tests check.)

    o.paths = {"opencl"};
    EXPECT_THROW(run_session_bench(o), Error);
}

}  // namespace
}  // namespace tridex::bench
