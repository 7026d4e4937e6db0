// The study's rank statistics checked against textbook examples with published answers, and the trial table's
// refusals of bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "app/commands/study/rank_tests.hpp"
#include "app/commands/study/study_stats.hpp"
#include "app/scene/trial_table.hpp"
#include "core/error.hpp"

namespace tridex::app::study {
namespace {

TEST(MidRanks, TiesShareTheMeanRank) {
    const std::vector<double> r = mid_ranks({3.0, 1.0, 3.0, 2.0, 3.0});
    EXPECT_EQ(r, (std::vector<double>{4.0, 1.0, 4.0, 2.0, 4.0}));
    EXPECT_EQ(tie_group_sizes({3.0, 1.0, 3.0, 2.0, 3.0, 1.0}), (std::vector<std::size_t>{2, 3}));
    EXPECT_THROW(mid_ranks({1.0, std::nan("")}), Error);
}

// Wikipedia, "Spearman's rank correlation coefficient", worked example (IQ against hours of TV per week, ten
// people): rho = -29/165 = -0.175757..., p = 0.627188 from the t distribution with 8 degrees of freedom.
TEST(Spearman, WikipediaIqAgainstTelevision) {
    const std::vector<double> iq{106, 100, 86, 101, 99, 103, 97, 113, 112, 110};
    const std::vector<double> tv{7, 27, 2, 50, 28, 29, 20, 12, 6, 17};
    const SpearmanResult s = spearman(iq, tv);
    EXPECT_EQ(s.n, 10u);
    EXPECT_NEAR(s.r, -29.0 / 165.0, 1e-12);
    EXPECT_NEAR(s.p_t, 0.627188, 1e-6);
    EXPECT_TRUE(std::isnan(s.p_exact)) << "n = 10 is above the exact limit";
}

// Hollander and Wolfe (1973), p. 185, the example of R's cor.test documentation: rho = 0.6 (S = 48).
TEST(Spearman, HollanderWolfeAggressionData) {
    const std::vector<double> x{44.4, 45.9, 41.9, 53.3, 44.7, 44.1, 50.7, 45.2, 60.1};
    const std::vector<double> y{2.6, 3.1, 2.5, 5.0, 3.6, 4.0, 5.2, 2.8, 3.8};
    EXPECT_NEAR(spearman(x, y).r, 0.6, 1e-12);
}

// With ties the coefficient is the Pearson correlation of the mid-ranks. x = (1, 2, 2, 3), y = (1, 3, 2, 4) have
// ranks (1, 2.5, 2.5, 4) and (1, 3, 2, 4): deviations (-1.5, 0, 0, 1.5) and (-1.5, 0.5, -0.5, 1.5), so
// r = 4.5 / sqrt(4.5 * 5) = sqrt(0.9) by hand; the no-ties formula 1 - 6 sum d^2 / (n (n^2 - 1)) would give 0.95.
TEST(Spearman, TiesUseMidRanksNotTheShortcutFormula) {
    EXPECT_NEAR(spearman({1, 2, 2, 3}, {1, 3, 2, 4}).r, std::sqrt(0.9), 1e-12);
    EXPECT_TRUE(std::isnan(spearman({1, 1, 1}, {1, 2, 3}).r));
    EXPECT_NEAR(spearman({1, 2, 3}, {3, 2, 1}).r, -1.0, 1e-15);
    EXPECT_THROW(spearman({1.0}, {2.0}), Error);
    EXPECT_THROW(spearman({1.0, 2.0}, {2.0}), Error);
}

// Hollander and Wolfe (1973), p. 69, permeability constants (the example of R's wilcox.test documentation):
// W = 35 for x; the exact one-sided p is 0.1272 (so two-sided 0.2544), and the normal approximation without
// continuity correction gives a two-sided p of 0.2207 (R: wilcox.test(x, y, exact = FALSE, correct = FALSE)).
TEST(MannWhitney, HollanderWolfePermeability) {
    const std::vector<double> x{0.80, 0.83, 1.89, 1.04, 1.45, 1.38, 1.91, 1.64, 0.73, 1.46};
    const std::vector<double> y{1.15, 0.88, 0.90, 0.74, 1.21};
    const MannWhitneyResult m = mann_whitney(x, y);
    EXPECT_DOUBLE_EQ(m.u1, 35.0);
    EXPECT_DOUBLE_EQ(m.u2, 15.0);
    EXPECT_DOUBLE_EQ(m.u, 15.0);
    EXPECT_FALSE(m.ties);
    EXPECT_NEAR(m.p_exact, 2 * 0.1272, 2e-4);
    EXPECT_NEAR(m.p_normal, 0.2207, 1e-4);
    EXPECT_LT(m.z, 0.0);
    // The test is symmetric in the samples.
    const MannWhitneyResult r = mann_whitney(y, x);
    EXPECT_DOUBLE_EQ(r.u, m.u);
    EXPECT_DOUBLE_EQ(r.p_normal, m.p_normal);
    EXPECT_NEAR(r.p_exact, m.p_exact, 1e-12);
}

// SciPy's scipy.stats.mannwhitneyu documentation (ages of male and female staff): U1 = 17, exact two-sided
// p = 0.1111 (= 14/126: 14 of the C(9, 4) = 126 splits are as extreme).
TEST(MannWhitney, ScipyStaffAges) {
    const MannWhitneyResult m = mann_whitney({19, 22, 16, 29, 24}, {20, 11, 17, 12});
    EXPECT_DOUBLE_EQ(m.u1, 17.0);
    EXPECT_NEAR(m.p_exact, 14.0 / 126.0, 1e-12);
}

std::vector<double> repeat_levels(const std::vector<int>& counts) {
    std::vector<double> v;
    for (std::size_t level = 0; level < counts.size(); ++level)
        for (int i = 0; i < counts[level]; ++i) v.push_back(static_cast<double>(level + 1));
    return v;
}

// Heavily tied ordinal data with published R answers (García Prado, statistical inference exercises 9 and 10 of
// garciparedes/r-examples, R's wilcox.test with correct = FALSE, which applies the tie correction):
//  - exercise 10: levels 1..6 with counts (60, 21, 11, 4, 3, 1) against (130, 50, 10, 6, 4, 0):
//    W = 10756, two-sided p = 0.2123 (0.2858 without the tie correction);
//  - exercise 9: counts (7, 9, 15, 9) against (5, 7, 16, 12): W = 700, one-sided p (greater) = 0.8431.
TEST(MannWhitney, TieCorrectionMatchesPublishedAnswers) {
    const MannWhitneyResult e10 = mann_whitney(repeat_levels({60, 21, 11, 4, 3, 1}), repeat_levels({130, 50, 10, 6, 4, 0}));
    EXPECT_DOUBLE_EQ(e10.u1, 10756.0);
    EXPECT_TRUE(e10.ties);
    EXPECT_NEAR(e10.p_normal, 0.2123, 1e-4);
    EXPECT_TRUE(std::isnan(e10.p_exact));  // N = 300: above the exact limit
    const MannWhitneyResult e9 = mann_whitney(repeat_levels({7, 9, 15, 9}), repeat_levels({5, 7, 16, 12}));
    EXPECT_DOUBLE_EQ(e9.u1, 700.0);
    EXPECT_NEAR(e9.p_normal, 2.0 * (1.0 - 0.8431), 2e-4);
}

// The exact p with ties, against a brute-force count of every split of the pooled sample.
TEST(MannWhitney, ExactWithTiesEqualsBruteForce) {
    const std::vector<double> a{1, 2, 2, 4, 5, 5}, b{2, 3, 5, 6, 6};
    const MannWhitneyResult m = mann_whitney(a, b);
    std::vector<double> pooled = a;
    pooled.insert(pooled.end(), b.begin(), b.end());
    const std::vector<double> ranks = mid_ranks(pooled);
    const double mean = 0.5 * a.size() * (pooled.size() + 1.0);
    double observed = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) observed += ranks[i];
    int all = 0, extreme = 0;
    for (unsigned mask = 0; mask < (1u << pooled.size()); ++mask) {
        if (__builtin_popcount(mask) != static_cast<int>(a.size())) continue;
        double sum = 0.0;
        for (std::size_t i = 0; i < pooled.size(); ++i)
            if (mask & (1u << i)) sum += ranks[i];
        ++all;
        extreme += std::fabs(sum - mean) >= std::fabs(observed - mean) - 1e-9;
    }
    EXPECT_EQ(all, 462);  // C(11, 6)
    EXPECT_NEAR(m.p_exact, static_cast<double>(extreme) / all, 1e-12);
    EXPECT_TRUE(m.ties);
}

TEST(MannWhitney, RefusesEmptyAndNonFinite) {
    EXPECT_THROW(mann_whitney({}, {1.0}), Error);
    EXPECT_THROW(mann_whitney({1.0}, {INFINITY}), Error);
    const MannWhitneyResult same = mann_whitney({2, 2}, {2, 2});
    EXPECT_EQ(same.z, 0.0);
    EXPECT_EQ(same.p_normal, 1.0);
    EXPECT_EQ(same.p_exact, 1.0);
}

// ---- the trial table -----------------------------------------------------------------------------------

std::filesystem::path write_csv(const std::string& name, const std::string& text) {
    const auto dir = std::filesystem::temp_directory_path() / "tridex_study_stats_test";
    std::filesystem::create_directories(dir);
    const auto p = dir / name;
    std::ofstream(p) << text;
    return p;
}

const char* kGood =
    "participant,group,trial,time_s,deviation_m\n"
    "P01,haptic,1,30.5,0.004\n"
    "P01,haptic,2,28,0.003\n"
    "P02,visual,1,25,0.006\n"
    "P02,visual,2,22.5,0.007\n";

// Expects read_trial_csv to refuse `text` with a message containing `what`.
void expect_refused(const std::string& name, const std::string& text, const std::string& what) {
    const auto p = write_csv(name, text);
    try {
        read_trial_csv(p.string());
        ADD_FAILURE() << name << ": accepted";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(p.string() + ":"), std::string::npos) << msg;
        EXPECT_NE(msg.find(what), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

TEST(TrialTable, ReadsAndRefusesBadRows) {
    const auto rows = read_trial_csv(write_csv("good.csv", kGood).string());
    ASSERT_EQ(rows.size(), 4u);
    EXPECT_EQ(rows[3].participant, "P02");
    EXPECT_DOUBLE_EQ(rows[3].time_s, 22.5);

    expect_refused("missing.csv", "participant,group,trial,time_s\nP01,haptic,1,3\n", ":1: field 'deviation_m': missing column");
    std::string s = kGood;
    expect_refused("nan.csv", s + "P03,visual,1,abc,0.1\n", ":6: field 'time_s': not a number");
    expect_refused("neg.csv", s + "P03,visual,1,3,-0.1\n", ":6: field 'deviation_m': negative");
    expect_refused("inf.csv", s + "P03,visual,1,inf,0.1\n", ":6: field 'time_s': not finite");
    expect_refused("group.csv", s + "P03,tactile,1,3,0.1\n", ":6: field 'group': unknown group 'tactile'");
    expect_refused("short.csv", s + "P03,visual,1,3\n", ":6: field 'deviation_m': missing");
    expect_refused("trial.csv", s + "P03,visual,0,3,0.1\n", ":6: field 'trial': not a positive integer");
    expect_refused("id.csv", s + "Jane Doe,visual,1,3,0.1\n", ":6: field 'participant'");
    expect_refused("both.csv", s + "P01,visual,3,3,0.1\n", ":6: field 'group': participant 'P01'");
    expect_refused("repeat.csv", s + "P01,haptic,2,3,0.1\n", ":6: field 'trial': participant 'P01' trial 2 repeats line 3");
    expect_refused("few.csv",
                   "participant,group,trial,time_s,deviation_m\nP01,haptic,1,3,0.1\nP02,visual,1,3,0.1\nP02,visual,2,3,0.1\n",
                   "field 'group': group 'haptic' has 1 trial; need at least two");
    expect_refused("empty.csv", "", "empty file");
}

TEST(TrialTable, WritesWhatItReads) {
    const auto p = write_csv("round.csv", kGood);
    const auto rows = read_trial_csv(p.string());
    const auto q = p.parent_path() / "round2.csv";
    write_trial_csv(q.string(), rows);
    const auto back = read_trial_csv(q.string());
    ASSERT_EQ(back.size(), rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        EXPECT_EQ(back[i].participant, rows[i].participant);
        EXPECT_EQ(back[i].trial, rows[i].trial);
        EXPECT_DOUBLE_EQ(back[i].deviation_m, rows[i].deviation_m);
    }
}

// The JSON has the shape, and the per-participant tests see one value per person.
TEST(StudyStats, JsonShapeAndPerParticipantMeans) {
    const std::string text = std::string(kGood) + "P03,haptic,1,40,0.002\nP03,haptic,2,38,0.001\n" +
                             "P04,visual,1,20,0.009\nP04,visual,2,21,0.008\n";
    const nlohmann::json j = study_stats_json(read_trial_csv(write_csv("shape.csv", text).string()));
    EXPECT_TRUE(j["spearman"]["visual"].is_number());
    EXPECT_TRUE(j["spearman"]["haptic"].is_number());
    for (const char* m : {"time_s", "deviation_m"})
        for (const char* k : {"U", "z", "p_normal", "p_exact"}) EXPECT_TRUE(j["mann_whitney"][m].contains(k)) << m << k;
    // Per trial: haptic times {30.5, 28, 40, 38} all above visual {25, 22.5, 20, 21}: U = 0, exact p = 2/70.
    EXPECT_DOUBLE_EQ(j["mann_whitney"]["time_s"]["U"].get<double>(), 0.0);
    EXPECT_NEAR(j["mann_whitney"]["time_s"]["p_exact"].get<double>(), 2.0 / 70.0, 1e-12);
    const nlohmann::json& pp = j["per_participant"];
    EXPECT_EQ(pp["mann_whitney"]["time_s"]["n1"].get<int>(), 2);
    EXPECT_NEAR(pp["participants"]["P01"]["time_s"].get<double>(), 29.25, 1e-12);
    // Two people per group: U = 0 of C(4, 2) = 6 splits, exact two-sided p = 2/6.
    EXPECT_NEAR(pp["mann_whitney"]["time_s"]["p_exact"].get<double>(), 1.0 / 3.0, 1e-12);
    const std::string table = study_stats_table(j);
    EXPECT_NE(table.find("Mann-Whitney U"), std::string::npos);
    EXPECT_NE(table.find("per-participant means"), std::string::npos);
}

}  // namespace
}  // namespace tridex::app::study

namespace tridex::app::study {
namespace {

// The exact null distribution of Spearman's r for n = 3 without ties: the 6 pairings give r = 1, 0.5, 0.5, -0.5,
// -0.5, -1 (each pairing's sum of squared rank differences 0, 2, 2, 6, 6, 8). So |r| = 1 has two-sided p = 2/6 and
// |r| = 0.5 has p = 1, where the t approximation says 0 and 0.667.
TEST(StudyStats, SpearmanExactPForSmallSamplesCountsEveryPairing) {
    const SpearmanResult one = spearman({1.0, 2.0, 3.0}, {10.0, 20.0, 30.0});
    EXPECT_DOUBLE_EQ(one.r, 1.0);
    EXPECT_DOUBLE_EQ(one.p_exact, 2.0 / 6.0);
    const SpearmanResult half = spearman({1.0, 2.0, 3.0}, {10.0, 30.0, 20.0});
    EXPECT_DOUBLE_EQ(half.r, 0.5);
    EXPECT_DOUBLE_EQ(half.p_exact, 1.0);
    // n = 4 without ties (r = 1 - sum d^2 / 10): of the 24 pairings one gives r = 1 and three give r = 0.8 (sum d^2 = 2),
    // and as many give -1 and -0.8, so p = 8/24 for |r| >= 0.8.
    const SpearmanResult four = spearman({1.0, 2.0, 3.0, 4.0}, {1.0, 2.0, 4.0, 3.0});
    EXPECT_DOUBLE_EQ(four.r, 0.8);
    EXPECT_DOUBLE_EQ(four.p_exact, 8.0 / 24.0);
}

}  // namespace
}  // namespace tridex::app::study
