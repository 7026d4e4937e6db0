// compute/contour/tile_change_log.hpp - which tiles changed after a mark, so that a reader of a tiled surface can
// visit those instead of every tile.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace tridex::compute {

std::uint64_t fresh_tile_version();  // compute/contour/contour_dual.hpp

/// An append-only record of (stamp, tile) pairs, stamps from fresh_tile_version() in the order they were taken, so
/// that since(mark) lists the tiles recorded after `mark` (another fresh_tile_version() value) in O(log n + answer).
/// It keeps at most max_entries() entries: past that it drops its older half, and a mark older than what it still
/// holds gets no answer (since() returns false: the reader then visits every tile). A copy is a record of its own,
/// empty, with an id of its own (the copied object changes apart from the original from then on). Not thread-safe.
class TileChangeLog {
public:
    /// The most entries any record keeps (16 bytes each).
    static constexpr std::size_t kMaxEntries = std::size_t{1} << 20;
    /// The entries worth keeping for a surface of `tiles` tiles: twice its tiles (a reader further behind visits
    /// every tile at about the same cost), within 4,096..kMaxEntries.
    static constexpr std::size_t entries_for(std::size_t tiles) {
        return std::clamp<std::size_t>(2 * tiles, 4096, kMaxEntries);
    }
    /// An empty record keeping at most `max_entries` entries (clamped to 2..kMaxEntries): marks taken before now get
    /// no answer (its owner's state before it was made is not recorded).
    explicit TileChangeLog(std::size_t max_entries = kMaxEntries)
        : max_(std::clamp<std::size_t>(max_entries, 2, kMaxEntries)), floor_(fresh_tile_version()), id_(floor_) {}
    TileChangeLog(const TileChangeLog& other) : TileChangeLog(other.max_) {}
    TileChangeLog& operator=(const TileChangeLog& other) {
        if (this != &other) *this = TileChangeLog(other.max_);
        return *this;
    }
    TileChangeLog(TileChangeLog&&) noexcept = default;
    TileChangeLog& operator=(TileChangeLog&&) noexcept = default;
    ~TileChangeLog() = default;
    /// Records that tile `tile` changed at `stamp` (a fresh_tile_version() value at least as new as any recorded).
    void add(std::uint64_t stamp, std::uint64_t tile) {
        if (entries_.size() >= max_) {
            const std::size_t drop = entries_.size() / 2;
            floor_ = entries_[drop - 1].first;
            entries_.erase(entries_.begin(), entries_.begin() + static_cast<std::ptrdiff_t>(drop));
        }
        entries_.emplace_back(stamp, tile);
    }
    /// Appends to `out` the tiles recorded with a stamp after `mark` (unsorted, with repeats) and returns true; returns
    /// false (out unchanged) when entries after `mark` may have been dropped, or made before the record was.
    bool since(std::uint64_t mark, std::vector<std::uint64_t>& out) const {
        if (mark < floor_) return false;
        const auto first = std::upper_bound(
            entries_.begin(), entries_.end(), mark,
            [](std::uint64_t m, const std::pair<std::uint64_t, std::uint64_t>& e) { return m < e.first; });
        for (auto it = first; it != entries_.end(); ++it) out.push_back(it->second);
        return true;
    }
    /// A value identifying this record among all records of the process (its creation stamp).
    std::uint64_t id() const { return id_; }
    /// The most entries it keeps.
    std::size_t max_entries() const { return max_; }

private:
    std::size_t max_;
    std::uint64_t floor_;  // no answer for a mark before this
    std::uint64_t id_;
    std::vector<std::pair<std::uint64_t, std::uint64_t>> entries_;
};

/// One TileMeshSource::change_view value for a source that shows `base`'s tiles through a filter with its own log
/// `filter` (ids from TileChangeLog::id()); 0 when `base` is 0 (keeps no record).
constexpr std::uint64_t combine_change_views(std::uint64_t base, std::uint64_t filter) {
    return base == 0 ? 0 : base * 0x9E3779B97F4A7C15ull + filter;
}

}  // namespace tridex::compute
