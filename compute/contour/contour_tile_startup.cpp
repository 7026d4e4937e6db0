// compute/contour/contour_tile_startup.cpp - TileSurfaceCache in a coarse-first start-up: the groups over tiles not
// contoured yet, which of them must be drawn coarse, and the finer coarse depths read after the first publish.
#include <algorithm>
#include <chrono>
#include <numeric>
#include <optional>
#include <unordered_set>

#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/sorted_ids.hpp"
#include "compute/contour/tile_group_box.hpp"
#include "core/error.hpp"

namespace tridex::compute {

void TileSurfaceCache::expect_tiles(const std::vector<std::uint64_t>& ids) {
    if (refreshed_) throw Error("TileSurfaceCache::expect_tiles: call it before the first refresh()");
    if (!coarse_) throw Error("TileSurfaceCache::expect_tiles: call use_coarse_groups() first");
    expected_.insert(ids.begin(), ids.end());
    startup_groups_ = true;
}

void TileSurfaceCache::defer_tiles(const std::vector<std::uint64_t>& ids) {
    if (!coarse_) throw Error("TileSurfaceCache::defer_tiles: call use_coarse_groups() first");
    if (!refreshed_) throw Error("TileSurfaceCache::defer_tiles: call it after the first refresh()");
    for (const std::uint64_t id : ids) {
        expected_.insert(id);
        stroke_expected_.insert(id);
    }
    stroke_changes_.insert(stroke_changes_.end(), ids.begin(), ids.end());
    if (!ids.empty()) startup_groups_ = true;
}

void TileSurfaceCache::arrive(const std::vector<std::uint64_t>& ids) {
    for (const std::uint64_t id : ids) {
        if (expected_.erase(id) == 0) continue;
        expected_left_.push_back(id);
        arrived_.insert(id);
        if (stroke_expected_.erase(id) > 0) stroke_arrived_.insert(id);
    }
}

void TileSurfaceCache::stop_expecting(const std::vector<std::uint64_t>& ids) {
    for (const std::uint64_t id : ids) {
        if (expected_.erase(id) != 0) expected_left_.push_back(id);
        stroke_expected_.erase(id);
    }
}

bool TileSurfaceCache::build_coarse_depth() {
    if (!coarse_) return false;
    for (int d = coarse_->max_depth(); d >= coarse_->min_depth(); --d) {
        if (coarse_->has_depth(d)) continue;
        const auto t0 = std::chrono::steady_clock::now();
        coarse_->build_depth(*coarse_model_, d);
        // The groups of that depth waiting for their levels get them through collect_lods(), a bounded number per
        // call, so that the caller (the sculpt thread) is not held for thousands of levels at once.
        lod_build_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (startup_groups_) update_startup_groups();
        return true;
    }
    return false;
}

Aabb TileSurfaceCache::expected_tile_box(std::uint64_t id, const std::array<int, 3>& dims) const {
    constexpr int kT = TileGrid::kTileCells;
    const auto nx = static_cast<std::uint64_t>(dims[0]), ny = static_cast<std::uint64_t>(dims[1]);
    const Vec3 c(static_cast<double>(id % nx), static_cast<double>((id / nx) % ny), static_cast<double>(id / (nx * ny)));
    const Lattice& l = coarse_model_->lattice;
    return Aabb{l.to_world(c * static_cast<double>(kT) - Vec3(1.0)), l.to_world((c + Vec3(1.0)) * static_cast<double>(kT) + Vec3(1.0))};
}

std::vector<bool> TileSurfaceCache::groups_refined(bool startup_only) const {
    std::vector<bool> refined(groups_.size(), true);
    if (expected_.empty() || (startup_only && startup_expected() == 0)) return refined;
    // groups_ is ordered by depth: children before their parents.
    for (std::size_t g = 0; g < groups_.size(); ++g) {
        const TileGroupSurface& group = groups_[g];
        for (const std::uint64_t c : group.children) {
            if (group.depth == 1 ? tile_expected(c, startup_only) : !refined[std::min(index_of(groups_, c), g)]) {
                refined[g] = false;
                break;
            }
        }
    }
    return refined;
}

bool TileSurfaceCache::group_refined(const TileGroupSurface& group, bool startup_only) const {
    if (expected_.empty() || (startup_only && startup_expected() == 0)) return true;
    for (const std::uint64_t c : group.children) {
        if (group.depth == 1) {
            if (tile_expected(c, startup_only)) return false;
        } else {
            const std::size_t ci = index_of(groups_, c);
            if (ci < groups_.size() && !group_refined(groups_[ci], startup_only)) return false;
        }
    }
    return true;
}

void TileSurfaceCache::stroke_pass_groups(std::vector<std::size_t>& visit, std::vector<bool>& refined) const {
    std::unordered_set<std::uint64_t> over;  // the groups over an expected tile
    for (const std::uint64_t t : expected_) {
        const std::uint64_t group = tile_group_id(1, group_index_of(grid_coords(t, coarse_dims_), coarse_dims_, 1));
        std::size_t g = index_of(groups_, group);
        // Only a tile its group lists counts (one deferred since the last regrouping does not yet, as in the whole
        // pass: groups_refined).
        if (g < groups_.size() && !std::binary_search(groups_[g].children.begin(), groups_[g].children.end(), t))
            continue;
        while (g < groups_.size() && over.insert(groups_[g].id).second)  // up its parents, to one already seen
            g = groups_[g].parent == TileGroupSurface::kNone ? groups_.size() : index_of(groups_, groups_[g].parent);
    }
    std::vector<std::uint64_t> ids(over.begin(), over.end());
    ids.insert(ids.end(), uncovered_.begin(), uncovered_.end());
    // Of the refined groups whose level waits, a pass measures the first kStartupErrorsPerPass in id order, and
    // notes from the next one that more wait: only those are looked at.
    std::vector<std::uint64_t> waiting;
    for (const std::uint64_t id : provisional_)
        if (over.count(id) == 0) waiting.push_back(id);
    std::sort(waiting.begin(), waiting.end());
    std::size_t taken = 0;
    for (auto it = waiting.begin(); it != waiting.end() && taken <= kStartupErrorsPerPass; ++it)
        if (index_of(groups_, *it) < groups_.size()) {
            ids.push_back(*it);
            ++taken;
        }
    for (const std::uint64_t id : ids)
        if (const std::size_t g = index_of(groups_, id); g < groups_.size()) visit.push_back(g);
    std::sort(visit.begin(), visit.end());
    visit.erase(std::unique(visit.begin(), visit.end()), visit.end());
    refined.reserve(visit.size());
    for (const std::size_t g : visit) refined.push_back(over.count(groups_[g].id) == 0);
}

bool TileSurfaceCache::startup_error_may_wait(const TileGroupSurface& group, bool refined) const {
    if (provisional_.count(group.id) == 0) return false;
    return refined || (group.depth > coarse_->min_depth() && estimated_.count(group.id) == 0 &&
                       coarse_->has_depth(coarse_->min_depth()) && !group.lods.empty());
}

void TileSurfaceCache::rate_startup_error(TileGroupSurface& group, bool refined, ErrorsRated& rated) {
    if (!startup_error_may_wait(group, refined)) return;
    // Its level's error, now that its tiles are all in (a few per pass: each reads its tiles' vertices).
    if (refined) {
        if (rated.measured == kStartupErrorsPerPass) {
            remeasure_more_ = true;
            return;
        }
        provisional_.erase(group.id);
        estimated_.erase(group.id);
        ++rated.measured;
        ++startup_errors_rated_;
        if (!group.lods.empty() && !group.lods.front().mesh.triangles.empty())
            group.lods.front().error_m = coarse_level_error(group, group.lods.front());
        group.version = fresh_tile_version();
        return;
    }
    // A deeper level built before its tiles: its estimate raised to how far the finest coarse depth's levels under it
    // lie from it, once they are read (a thin feature its stride missed shows there first). Only while start-up's
    // tiles are expected under it: a stroke's deferred group is measured against the tiles in
    // (rebuild_coarse_levels). Each try walks the group's finest levels, so a pass tries a bounded number; once it
    // has found that more wait than it tries, a candidate's own walk (group_refined) is skipped: it could only say
    // again that more wait.
    if ((rated.estimates_full() && remeasure_more_) || group_refined(group, true)) return;
    ++rated.tried;
    if (rated.estimates_full()) {
        remeasure_more_ = true;
    } else if (const std::optional<double> e = coarse_level_estimate(group, group.lods.front())) {
        ++rated.estimated;
        ++startup_errors_rated_;
        estimated_.insert(group.id);
        if (*e > group.lods.front().error_m) {
            group.lods.front().error_m = *e;
            group.version = fresh_tile_version();
        }
    }
}

void TileSurfaceCache::update_startup_groups(bool measure) {
    // With start-up's tiles all in, only the groups stroke_pass_groups() names may change; else every group.
    std::vector<std::size_t> visit;
    std::vector<bool> refined;
    if (startup_expected() == 0 && !pass_every_group_) {
        stroke_pass_groups(visit, refined);
    } else {
        refined = groups_refined();
        visit.resize(groups_.size());
        std::iota(visit.begin(), visit.end(), std::size_t{0});
    }
    last_group_pass_visits_ = visit.size();
    bool open = !expected_.empty();
    ErrorsRated rated;
    remeasure_more_ = false;
    uncovered_.clear();
    for (std::size_t k = 0; k < visit.size(); ++k) {  // children before their parents
        const std::size_t g = visit[k];
        TileGroupSurface& group = groups_[g];
        bool cover = refined[k];
        if (!cover && group.depth > 1) {  // smaller groups stand in where they are refined or have a level
            // A smaller group whose current coarse read found no surface stands in too: it has nothing to draw
            // until its tiles arrive (no surface, or a feature thinner than its stride), whatever is drawn above it.
            cover = true;
            for (const std::uint64_t c : group.children) {
                const std::size_t ci = index_of(groups_, c);
                if (ci >= g) continue;
                const TileGroupSurface& child = groups_[ci];
                const bool read_empty = coarse_->has_depth(child.depth) && coarse_stale_.count(child.id) == 0;
                if (!child.children_cover && child.lods.empty() && !read_empty) {
                    cover = false;
                    break;
                }
            }
        }
        if (cover != group.children_cover) {
            group.children_cover = cover;
            group.version = fresh_tile_version();
        }
        if (measure)
            rate_startup_error(group, refined[k], rated);
        else if (!remeasure_more_)  // a pass that sets the cover only leaves what waits to a later one
            remeasure_more_ = startup_error_may_wait(group, refined[k]);
        if (!group.children_cover) uncovered_.push_back(group.id);
        open = open || !group.children_cover;
    }
    startup_groups_ = open || !provisional_.empty();
}

}  // namespace tridex::compute
