// core/text/nearest_name.hpp - "did you mean": the known name nearest to a mistyped one, by edit distance.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace tridex {

/// Levenshtein distance between a and b: the fewest single-character insertions, deletions and substitutions that
/// turn one into the other. O(|a| * |b|) time, O(|b|) memory.
std::size_t edit_distance(const std::string& a, const std::string& b);

/// The name of `known` nearest to `typed` when it is at most `max_distance` edits away and closer than a third of
/// the typed name's length rounded up (so "x" suggests nothing), else "". Ties go to the first in `known`.
std::string nearest_name(const std::string& typed, const std::vector<std::string>& known, std::size_t max_distance = 3);

}  // namespace tridex
