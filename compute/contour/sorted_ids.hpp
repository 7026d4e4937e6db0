// compute/contour/sorted_ids.hpp - lookups by id in the tile cache's lists of tiles and groups, which are kept sorted
// by id.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <utility>
#include <vector>

namespace tridex::compute {

/// The index of the entry whose `id` member equals `id` in `sorted` (ascending by id), or sorted.size() when there
/// is none. O(log n).
template <typename T>
std::size_t index_of(const std::vector<T>& sorted, std::uint64_t id) {
    const auto it = std::lower_bound(sorted.begin(), sorted.end(), id, [](const T& x, std::uint64_t v) { return x.id < v; });
    return it != sorted.end() && it->id == id ? static_cast<std::size_t>(it - sorted.begin()) : sorted.size();
}

/// The entry whose `id` member equals `id` in `sorted` (ascending by id), or nullptr. O(log n).
template <typename T>
const T* find_by_id(const std::vector<T>& sorted, std::uint64_t id) {
    const std::size_t i = index_of(sorted, id);
    return i < sorted.size() ? &sorted[i] : nullptr;
}

/// Adds the ids of `add` (ascending, no repeats) to `into` (ascending, no repeats), which stays so. O(n + m).
inline void merge_ids(std::vector<std::uint64_t>& into, const std::vector<std::uint64_t>& add) {
    if (add.empty()) return;
    std::vector<std::uint64_t> out;
    out.reserve(into.size() + add.size());
    std::set_union(into.begin(), into.end(), add.begin(), add.end(), std::back_inserter(out));
    into = std::move(out);
}

}  // namespace tridex::compute
