// `tridex bench --soak` (bench/soak/bench_soak): the short form CI runs, a 2-minute soak of the full run session that fails
// when resident memory grows beyond kSoakGrowthBoundMbPerMin after the first minute or descriptors or threads
// pile up; and the verdict's arithmetic, which never calls a run without two minutes "met".
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "bench/soak/bench_soak.hpp"

namespace tridex::bench {
namespace {

namespace fs = std::filesystem;

SoakMinute minute(int m, double rss_mb) {
    SoakMinute s;
    s.minute = m;
    s.rss_mb = rss_mb;
    s.fds = 10;
    s.threads = 12;
    s.journal_mb = 0.5 * m;
    return s;
}

TEST(BenchSoakVerdict, OneMinuteIsNotMeasured) {
    SoakResult r;
    r.minutes = {minute(1, 300.0)};
    judge_soak(r);
    EXPECT_EQ(r.verdict, Verdict::kNotMeasured);
    EXPECT_FALSE(target_met(r.verdict));
    SoakResult none;
    judge_soak(none);
    EXPECT_EQ(none.verdict, Verdict::kNotMeasured);
}

TEST(BenchSoakVerdict, SlopeAfterTheFirstMinuteAgainstTheBound) {
    SoakResult flat;
    flat.minutes = {minute(1, 300.0), minute(2, 301.0), minute(3, 300.5), minute(4, 301.5)};
    judge_soak(flat);
    EXPECT_NEAR(flat.growth_mb_per_min, 0.4, 1e-9);
    EXPECT_EQ(flat.verdict, Verdict::kMet);
    EXPECT_NEAR(flat.journal_mb_per_hour, 30.0, 1e-9);  // 0.5 MB a minute
    SoakResult leak;
    leak.minutes = {minute(1, 300.0), minute(2, 305.0), minute(3, 310.0)};
    judge_soak(leak);
    EXPECT_NEAR(leak.growth_mb_per_min, 5.0, 1e-9);
    EXPECT_EQ(leak.verdict, Verdict::kOver);
}

TEST(BenchSoak, TwoMinutesOfSculptingKeepMemoryFilesAndThreadsFlat) {
    SoakOptions o;
    o.minutes = 2.0;
    o.resolution = 96;
    o.out = (fs::temp_directory_path() / ("tridex_test_bench_soak_" + std::to_string(::getpid()))).string();
    fs::remove_all(o.out);
    const SoakResult r = run_soak_bench(o);
    ASSERT_EQ(r.minutes.size(), 2u) << r.ended;
    for (const SoakMinute& m : r.minutes) {
        SCOPED_TRACE("minute " + std::to_string(m.minute));
        EXPECT_GT(m.frames, 600u);     // paced at 60 Hz: 3600 a minute on an idle machine
        EXPECT_GT(m.ticks, 30000u);    // the 1 kHz loop ran the whole minute
        EXPECT_GT(m.steps, 10u);       // the sculptor kept sculpting
        EXPECT_GT(m.frame_p99_ms, 0.0);
        EXPECT_GT(m.period_p99_us, 0.0);
        EXPECT_GE(m.period_worst_us, m.period_p99_us);
        EXPECT_GT(m.step_p99_ms, 0.0);
        EXPECT_GT(m.rss_mb, 10.0);
        EXPECT_GT(m.journal_mb, 0.0);
        EXPECT_GT(m.history_budget_mb, 0.0);
        EXPECT_LE(m.history_mb, m.history_budget_mb);
    }
    EXPECT_GT(r.minutes[1].journal_mb, r.minutes[0].journal_mb);  // the journal stays on
    // The bound (bench_soak.hpp says why it is 3 MB/min) is the long runs'. Over one minute the heap (its least over
    // the minute's last 15 s) and resident memory also follow the surface drawn, whose full-resolution tiles wait
    // longer for their levels of detail when other programs share the cores (ctest -j 2), then flat or falling over
    // the minutes after (docs/benchmarks/soak.md). So two minutes get twice the bound on the heap and three times on
    // resident memory: a tile mesh leaked per sculpt step still exceeds both. The bench's longer runs judge the bound.
    const double heap_growth_mb = r.minutes[1].heap_mb - r.minutes[0].heap_mb;
    EXPECT_LE(heap_growth_mb, 2.0 * kSoakGrowthBoundMbPerMin) << "the heap grew " << heap_growth_mb << " MB after minute 1";
    EXPECT_LE(r.growth_mb_per_min, 3.0 * kSoakGrowthBoundMbPerMin)
        << "resident memory grew " << r.growth_mb_per_min << " MB/min after minute 1";
    EXPECT_EQ(r.verdict, r.growth_mb_per_min <= kSoakGrowthBoundMbPerMin ? Verdict::kMet : Verdict::kOver);
    // Descriptors and threads flat: a save, a checkpoint or an undo that kept a file or a thread would show here.
    EXPECT_LE(r.fds_last, r.fds_first + 2) << "open descriptors";
    EXPECT_LE(r.threads_last, r.threads_first + 1) << "threads";
    EXPECT_GE(r.recover_s, 0.0);
    EXPECT_LT(r.recover_s, 30.0);
    // The files: a JSON row per minute, and the summary with its verdict.
    std::ifstream rows(fs::path(o.out) / "soak.jsonl");
    std::string line;
    int n = 0;
    while (std::getline(rows, line)) {
        const nlohmann::json j = nlohmann::json::parse(line);
        EXPECT_EQ(j.at("minute").get<int>(), ++n);
        EXPECT_TRUE(j.contains("rss_mb") && j.contains("period_worst_us") && j.contains("threads"));
    }
    EXPECT_EQ(n, 2);
    const nlohmann::json s = nlohmann::json::parse(std::ifstream(fs::path(o.out) / "soak.json"));
    EXPECT_EQ(s.at("verdict").get<std::string>(), r.verdict == Verdict::kMet ? "target met" : "over target");
    EXPECT_EQ(s.at("rows").size(), 2u);
    EXPECT_TRUE(fs::exists(fs::path(o.out) / "soak.svg"));
    fs::remove_all(o.out);
}

}  // namespace
}  // namespace tridex::bench
