// A benchmark row's verdict against its target (bench/bench_verdict.hpp): a row with no timed sample is "not
// measured" and does not count as met, whatever its figures read (the quantiles of no samples read 0).
#include <gtest/gtest.h>

#include <string>

#include "bench/bench_session.hpp"
#include "bench/bench_verdict.hpp"

namespace tridex::bench {
namespace {

TEST(BenchVerdict, NoTimedSampleIsNotMeasuredAndNotMet) {
    EXPECT_EQ(verdict_of(0, true), Verdict::kNotMeasured);
    EXPECT_EQ(std::string(verdict_text(verdict_of(0, true))), "not measured");
    EXPECT_FALSE(target_met(verdict_of(0, true)));
    EXPECT_EQ(std::string(verdict_text(verdict_of(3, true))), "target met");
    EXPECT_TRUE(target_met(verdict_of(3, true)));
    EXPECT_EQ(std::string(verdict_text(verdict_of(3, false))), "over target");
    EXPECT_FALSE(target_met(verdict_of(3, false)));
}

// The push row of `bench --session` whose frames drew no timed change (lat timed at: none) used to print "target met".
TEST(BenchVerdict, ALatencyRowWithoutATimedFrameIsNotMeasured) {
    LatencyBenchRow row;
    row.op = "push";
    row.frames = 0;
    row.drawn_clock = "none";
    EXPECT_EQ(latency_verdict(row), Verdict::kNotMeasured);
    row.frames = 12;  // frames counted, but none of them timed
    EXPECT_EQ(latency_verdict(row), Verdict::kNotMeasured);
    row.drawn_clock = "gpu";
    row.p99_ms = 0.5 * kLatencyTargetMs;
    EXPECT_EQ(latency_verdict(row), Verdict::kMet);
    row.drawn_clock = "submit";  // timed at the submit alone: still a measurement
    EXPECT_EQ(latency_verdict(row), Verdict::kMet);
    row.p99_ms = 2.0 * kLatencyTargetMs;
    EXPECT_EQ(latency_verdict(row), Verdict::kOver);
    row.frames = 0;
    row.drawn_clock = "gpu";
    EXPECT_EQ(latency_verdict(row), Verdict::kNotMeasured);
}

}  // namespace
}  // namespace tridex::bench
