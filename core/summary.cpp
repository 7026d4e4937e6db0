// core/summary.cpp - nearest-rank order statistics.
#include "core/summary.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace tridex {

Summary summarize(std::vector<double> v) {
    Summary s;
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    auto rank = [&](double q) {
        const std::size_t k = static_cast<std::size_t>(std::ceil(q * v.size()));
        return v[std::min(v.size() - 1, k == 0 ? 0 : k - 1)];
    };
    s.median = rank(0.5);
    s.p99 = rank(0.99);
    s.max = v.back();
    s.mean = std::accumulate(v.begin(), v.end(), 0.0) / v.size();
    return s;
}

}  // namespace tridex
