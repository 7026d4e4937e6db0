// core/text/nearest_name.cpp - edit distance and the nearest known name.
#include "core/text/nearest_name.hpp"

#include <algorithm>

namespace tridex {

std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diag = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diag = up;
        }
    }
    return row[b.size()];
}

std::string nearest_name(const std::string& typed, const std::vector<std::string>& known, std::size_t max_distance) {
    // Closer than a third of the typed length (rounded up), and within max_distance.
    std::string best;
    std::size_t best_d = std::min(max_distance + 1, (typed.size() + 2) / 3);
    for (const std::string& k : known) {
        const std::size_t d = edit_distance(typed, k);
        if (d < best_d) {
            best_d = d;
            best = k;
        }
    }
    return best;
}

}  // namespace tridex
