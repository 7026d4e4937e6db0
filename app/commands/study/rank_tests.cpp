// app/commands/study/rank_tests.cpp - mid-ranks, Spearman's rho and the Mann-Whitney U test.
#include "app/commands/study/rank_tests.hpp"

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <numeric>
#include <string>

#include "core/error.hpp"

namespace tridex::app::study {

namespace {

void check_finite(const std::vector<double>& v, const char* what) {
    for (std::size_t i = 0; i < v.size(); ++i)
        if (!std::isfinite(v[i]))
            throw Error(std::string(what) + ": value " + std::to_string(i + 1) + " is not finite");
}

std::vector<std::size_t> ascending_order(const std::vector<double>& v) {
    std::vector<std::size_t> order(v.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
    return order;
}

double pearson(const std::vector<double>& x, const std::vector<double>& y) {
    const double n = static_cast<double>(x.size());
    const double mx = std::accumulate(x.begin(), x.end(), 0.0) / n;
    const double my = std::accumulate(y.begin(), y.end(), 0.0) / n;
    double sxy = 0.0, sxx = 0.0, syy = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        sxy += (x[i] - mx) * (y[i] - my);
        sxx += (x[i] - mx) * (x[i] - mx);
        syy += (y[i] - my) * (y[i] - my);
    }
    if (sxx <= 0.0 || syy <= 0.0) return std::nan("");
    return std::clamp(sxy / std::sqrt(sxx * syy), -1.0, 1.0);
}

// Two-sided exact p of the rank sum of a sample of n1 drawn from the pooled doubled mid-ranks `ranks2`
// (integers), for an observed doubled rank sum w2: the share of the C(N, n1) subsets whose sum is at least
// as far from its mean as w2.
double exact_two_sided_p(const std::vector<long>& ranks2, std::size_t n1, long w2) {
    const std::size_t n = ranks2.size();
    const long total = std::accumulate(ranks2.begin(), ranks2.end(), 0L);
    // counts[k][s]: subsets of size k of the items seen so far whose doubled rank sum is s.
    std::vector<std::vector<long double>> counts(n1 + 1, std::vector<long double>(static_cast<std::size_t>(total) + 1, 0.0L));
    counts[0][0] = 1.0L;
    for (std::size_t i = 0; i < n; ++i) {
        const long r = ranks2[i];
        for (std::size_t k = std::min(i + 1, n1); k >= 1; --k)
            for (long s = total - r; s >= 0; --s)
                if (counts[k - 1][static_cast<std::size_t>(s)] != 0.0L)
                    counts[k][static_cast<std::size_t>(s + r)] += counts[k - 1][static_cast<std::size_t>(s)];
    }
    const long mean2_times_n = static_cast<long>(n1) * total;  // mean of the sum, times N, in doubled units
    const long nn = static_cast<long>(n);
    const long d_obs = std::labs(w2 * nn - mean2_times_n);
    long double all = 0.0L, tail = 0.0L;
    for (long s = 0; s <= total; ++s) {
        const long double c = counts[n1][static_cast<std::size_t>(s)];
        all += c;
        if (std::labs(s * nn - mean2_times_n) >= d_obs) tail += c;
    }
    return static_cast<double>(std::min(1.0L, tail / all));
}

}  // namespace

std::vector<double> mid_ranks(const std::vector<double>& values) {
    check_finite(values, "ranks");
    const std::vector<std::size_t> order = ascending_order(values);
    std::vector<double> ranks(values.size());
    for (std::size_t i = 0; i < order.size();) {
        std::size_t j = i;
        while (j + 1 < order.size() && values[order[j + 1]] == values[order[i]]) ++j;
        const double mid = 0.5 * static_cast<double>(i + j) + 1.0;  // mean of ranks i+1 .. j+1
        for (std::size_t k = i; k <= j; ++k) ranks[order[k]] = mid;
        i = j + 1;
    }
    return ranks;
}

std::vector<std::size_t> tie_group_sizes(const std::vector<double>& values) {
    std::vector<double> v = values;
    std::sort(v.begin(), v.end());
    std::vector<std::size_t> sizes;
    for (std::size_t i = 0; i < v.size();) {
        std::size_t j = i;
        while (j + 1 < v.size() && v[j + 1] == v[i]) ++j;
        if (j > i) sizes.push_back(j - i + 1);
        i = j + 1;
    }
    return sizes;
}

SpearmanResult spearman(const std::vector<double>& x, const std::vector<double>& y) {
    if (x.size() != y.size())
        throw Error("spearman: the samples differ in size (" + std::to_string(x.size()) + " and " +
                    std::to_string(y.size()) + ")");
    if (x.size() < 2) throw Error("spearman: need at least two pairs, got " + std::to_string(x.size()));
    check_finite(x, "spearman x");
    check_finite(y, "spearman y");
    SpearmanResult res;
    res.n = x.size();
    const std::vector<double> rx = mid_ranks(x);
    std::vector<double> ry = mid_ranks(y);
    res.r = pearson(rx, ry);
    res.p_t = std::nan("");
    res.p_exact = std::nan("");
    if (res.n <= kSpearmanExactMaxN && std::isfinite(res.r)) {
        // Every pairing of y's ranks with x's; a small tolerance keeps pairings equal to the observed one counted.
        std::sort(ry.begin(), ry.end());
        std::size_t all = 0, extreme = 0;
        const double bar = std::fabs(res.r) - 1e-12;
        do {
            ++all;
            if (std::fabs(pearson(rx, ry)) >= bar) ++extreme;
        } while (std::next_permutation(ry.begin(), ry.end()));
        // next_permutation skips orderings equal under tied ranks; each distinct one stands for the same number
        // of the n! pairings, so the share is unchanged.
        res.p_exact = static_cast<double>(extreme) / static_cast<double>(all);
    }
    if (res.n >= 3 && std::isfinite(res.r)) {
        const double df = static_cast<double>(res.n - 2);
        if (std::fabs(res.r) >= 1.0) {
            res.p_t = 0.0;
        } else {
            const double t = res.r * std::sqrt(df / (1.0 - res.r * res.r));
            const boost::math::students_t dist(df);
            res.p_t = std::min(1.0, 2.0 * boost::math::cdf(boost::math::complement(dist, std::fabs(t))));
        }
    }
    return res;
}

MannWhitneyResult mann_whitney(const std::vector<double>& a, const std::vector<double>& b, std::size_t exact_max_n) {
    if (a.empty() || b.empty()) throw Error("mann_whitney: each sample needs at least one value");
    if (exact_max_n > kExactLimitN)
        throw Error("mann_whitney: exact_max_n " + std::to_string(exact_max_n) + " is above " +
                    std::to_string(kExactLimitN));
    check_finite(a, "mann_whitney a");
    check_finite(b, "mann_whitney b");
    std::vector<double> pooled = a;
    pooled.insert(pooled.end(), b.begin(), b.end());
    const std::vector<double> ranks = mid_ranks(pooled);

    MannWhitneyResult res;
    res.n1 = a.size();
    res.n2 = b.size();
    const double n1 = static_cast<double>(res.n1), n2 = static_cast<double>(res.n2), n = n1 + n2;
    res.rank_sum1 = std::accumulate(ranks.begin(), ranks.begin() + static_cast<std::ptrdiff_t>(res.n1), 0.0);
    res.u1 = res.rank_sum1 - n1 * (n1 + 1.0) / 2.0;
    res.u2 = n1 * n2 - res.u1;
    res.u = std::min(res.u1, res.u2);
    res.mean_u = n1 * n2 / 2.0;

    const std::vector<std::size_t> ties = tie_group_sizes(pooled);
    res.ties = !ties.empty();
    double tie_sum = 0.0;
    for (std::size_t t : ties) tie_sum += std::pow(static_cast<double>(t), 3) - static_cast<double>(t);
    const double var = n1 * n2 / 12.0 * ((n + 1.0) - (n > 1.0 ? tie_sum / (n * (n - 1.0)) : 0.0));
    res.sd_u = var > 0.0 ? std::sqrt(var) : 0.0;
    res.z = res.sd_u > 0.0 ? (res.u - res.mean_u) / res.sd_u : 0.0;
    const boost::math::normal standard;
    res.p_normal = std::min(1.0, 2.0 * boost::math::cdf(standard, -std::fabs(res.z)));

    if (pooled.size() <= exact_max_n) {
        std::vector<long> ranks2(ranks.size());
        for (std::size_t i = 0; i < ranks.size(); ++i) ranks2[i] = std::lround(2.0 * ranks[i]);
        res.p_exact = exact_two_sided_p(ranks2, res.n1, std::lround(2.0 * res.rank_sum1));
    } else {
        res.p_exact = std::nan("");
    }
    return res;
}

}  // namespace tridex::app::study
