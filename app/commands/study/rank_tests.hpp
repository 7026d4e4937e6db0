// app/commands/study/rank_tests.hpp - the rank statistics of the training study: mid-ranks, Spearman's rank
// correlation and the Mann-Whitney U test (normal approximation with the tie correction, and the exact
// permutation p for small samples). Singapogu, MS thesis (Clemson 2007), section 4.4.
#pragma once

#include <cstddef>
#include <vector>

namespace tridex::app::study {

/// Ranks 1..n of `values` in ascending order; tied values all get the mean of the ranks they span
/// (mid-ranks). Output has the input's order and size. Throws tridex::Error on a non-finite value.
std::vector<double> mid_ranks(const std::vector<double>& values);

/// Sizes t of the groups of tied values (only groups with t >= 2), in ascending order of the value.
std::vector<std::size_t> tie_group_sizes(const std::vector<double>& values);

/// Spearman's rank correlation of paired samples and its significance.
struct SpearmanResult {
    std::size_t n = 0;  ///< pairs
    double r = 0.0;     ///< rank correlation in [-1, 1]; NaN when either sample is constant
    /// Two-sided p of the t approximation t = r * sqrt((n - 2) / (1 - r^2)) with n - 2 degrees of freedom
    /// (Student's t from Boost.Math); NaN when n < 3 or r is NaN.
    double p_t = 0.0;
    /// Two-sided exact p: the share of the n! equally likely pairings (y's mid-ranks permuted against x's) whose
    /// |r| is at least the observed |r| (ties handled exactly); NaN when n > kSpearmanExactMaxN or r is NaN. For
    /// the small samples of a study (e.g. per-participant means) the t approximation is poor (|r| = 1 gives
    /// p_t = 0): use this one.
    double p_exact = 0.0;
};

/// Largest n for which spearman computes p_exact (9! = 362880 pairings).
inline constexpr std::size_t kSpearmanExactMaxN = 9;

/// Spearman's rho of (x_i, y_i): the Pearson correlation of the mid-ranks, which equals
/// 1 - 6 sum d^2 / (n (n^2 - 1)) when there are no ties (Spearman 1904; ties ranked by their mean rank as
/// in the thesis, 4.4). Throws tridex::Error when the sizes differ, n < 2 or a value is not finite.
SpearmanResult spearman(const std::vector<double>& x, const std::vector<double>& y);

/// The Mann-Whitney U test of two independent samples a and b (two-sided).
struct MannWhitneyResult {
    std::size_t n1 = 0, n2 = 0;  ///< sample sizes of a and b
    double rank_sum1 = 0.0;      ///< sum of a's mid-ranks in the pooled sample
    double u1 = 0.0;             ///< U of a: rank_sum1 - n1 (n1 + 1) / 2 (pairs where a beats b, ties count 1/2)
    double u2 = 0.0;             ///< U of b: n1 n2 - u1
    double u = 0.0;              ///< min(u1, u2), the statistic the thesis tabulates
    double mean_u = 0.0;         ///< n1 n2 / 2
    /// Standard deviation of U under H0 with the tie correction:
    /// sqrt(n1 n2 / 12 * ((N + 1) - sum(t^3 - t) / (N (N - 1)))), N = n1 + n2.
    double sd_u = 0.0;
    double z = 0.0;              ///< (u - mean_u) / sd_u (<= 0), no continuity correction; 0 when sd_u is 0
    double p_normal = 1.0;       ///< two-sided p of z under the standard normal (Boost.Math), 2 Phi(-|z|)
    /// Two-sided exact p: the share of the C(N, n1) equally likely splits of the pooled mid-ranks whose U is at
    /// least as far from mean_u as the observed one (ties handled exactly); NaN when N > exact_max_n.
    double p_exact = 0.0;
    bool ties = false;           ///< whether the pooled sample has tied values
};

/// Largest pooled sample N = n1 + n2 for which mann_whitney computes p_exact by default.
inline constexpr std::size_t kExactMaxN = 60;
/// Largest exact_max_n mann_whitney accepts.
inline constexpr std::size_t kExactLimitN = 120;

/// The Mann-Whitney U test (Mann and Whitney 1947; equivalently Wilcoxon's rank sum) of a against b, as in the
/// thesis's 4.4. Throws tridex::Error when a sample has fewer than one value, a value is not finite, or
/// exact_max_n exceeds kExactLimitN (the exact count's cost grows as N^4).
MannWhitneyResult mann_whitney(const std::vector<double>& a, const std::vector<double>& b,
                               std::size_t exact_max_n = kExactMaxN);

}  // namespace tridex::app::study
