// compute/contour/contour_tile_coarse.cpp - TileSurfaceCache's groups with levels contoured from the model read at
// coarser strides (CoarseGroupLevels): which a change reaches, and rebuilding them once the change settles.
#include <algorithm>
#include <chrono>
#include <optional>
#include <span>

#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/dexel_error.hpp"
#include "compute/contour/sorted_ids.hpp"
#include "compute/contour/surface_distance.hpp"
#include "compute/contour/tile_group_box.hpp"
#include "core/error.hpp"

namespace tridex::compute {

void TileSurfaceCache::use_coarse_groups(const TriDexel& model, const CoarseLevelOptions& options, bool coarse_first) {
    if (!lod_) throw Error("TileSurfaceCache::use_coarse_groups: call enable_lod() first");
    if (refreshed_) throw Error("TileSurfaceCache::use_coarse_groups: call it before the first refresh()");
    coarse_ = std::make_unique<CoarseGroupLevels>(model, options, coarse_first ? options.max_depth : 0);
    coarse_model_ = &model;
    lod_options_.group_depth = options.max_depth;
}

namespace {

// The cells of `group`'s tiles (inclusive).
CellBox group_cells(const TileGroupSurface& group) {
    constexpr int kT = TileGrid::kTileCells;
    const int span = 1 << group.depth;
    CellBox box;
    for (int a = 0; a < 3; ++a) {
        box.lo[a] = group.coords[a] * span * kT;
        box.hi[a] = (group.coords[a] + 1) * span * kT - 1;
    }
    return box;
}

// The tiles of `tiles` (ascending) whose coarse rays a level of one of the groups `ids` reads, in a grid of `dims`
// tiles: those within one group of it, at its depth, and the rays' reach (each group's range of tile coordinates,
// grown so). Ascending.
std::vector<std::uint64_t> tiles_near_groups(const std::vector<TileGroupSurface>& groups,
                                             const std::vector<std::uint64_t>& ids,
                                             const std::vector<std::uint64_t>& tiles, const std::array<int, 3>& dims) {
    constexpr int kT = TileGrid::kTileCells;
    std::vector<std::array<int, 6>> ranges;  // lo x, y, z, then hi (exclusive)
    for (const std::uint64_t id : ids) {
        const std::size_t g = index_of(groups, id);
        if (g == groups.size()) continue;
        const TileGroupSurface& group = groups[g];
        const int span = 1 << group.depth, grow = span + (TriDexel::kDirtyReachCells + kT - 1) / kT;
        std::array<int, 6> r{};
        for (int a = 0; a < 3; ++a) {
            r[a] = group.coords[a] * span - grow;
            r[3 + a] = (group.coords[a] + 1) * span + grow;
        }
        ranges.push_back(r);
    }
    std::vector<std::uint64_t> near;
    for (const std::uint64_t t : tiles) {
        const std::array<int, 3> tc = grid_coords(t, dims);
        const auto inside = [&](const std::array<int, 6>& r) {
            return tc[0] >= r[0] && tc[1] >= r[1] && tc[2] >= r[2] && tc[0] < r[3] && tc[1] < r[4] && tc[2] < r[5];
        };
        if (std::any_of(ranges.begin(), ranges.end(), inside)) near.push_back(t);
    }
    return near;
}

}  // namespace

std::unordered_set<std::uint64_t> TileSurfaceCache::coarse_reach(const std::array<int, 3>& dims,
                                                                 const std::vector<std::uint64_t>& changed_tiles) const {
    // A changed ray reaches kDirtyReachCells fine cells into the fine contour; the coarse contour reads the rays
    // kDirtyReachCells coarse cells around its own, and a group's ring takes one coarse cell past its box. So a group
    // is reached when its box, grown by (kDirtyReachCells + 1) coarse cells, meets the tile's grown by
    // kDirtyReachCells fine cells.
    constexpr int kT = TileGrid::kTileCells, kReach = TriDexel::kDirtyReachCells;
    std::unordered_set<std::uint64_t> out;
    for (int d = coarse_->min_depth(); d <= coarse_->max_depth(); ++d) {
        const int span = kT << d, grow = (kReach + 1) << d;
        const std::array<int, 3> gdims = group_grid_dims(dims, d);
        for (const std::uint64_t t : changed_tiles) {
            const std::array<int, 3> tc = grid_coords(t, dims);
            std::array<int, 3> lo{}, hi{};
            for (int a = 0; a < 3; ++a) {
                const int cell_lo = tc[a] * kT - kReach - grow, cell_hi = (tc[a] + 1) * kT + kReach + grow;  // [lo, hi)
                lo[a] = std::max(0, cell_lo < 0 ? -((-cell_lo + span - 1) / span) : cell_lo / span);
                hi[a] = std::min(gdims[a] - 1, (cell_hi - 1) / span);
            }
            for (int z = lo[2]; z <= hi[2]; ++z)
                for (int y = lo[1]; y <= hi[1]; ++y)
                    for (int x = lo[0]; x <= hi[0]; ++x) out.insert(tile_group_id(d, grid_index({x, y, z}, gdims)));
        }
    }
    return out;
}

std::size_t TileSurfaceCache::rebuild_coarsest_now(const std::array<int, 3>& dims,
                                                   const std::vector<std::uint64_t>& changed, bool stroke_hidden) {
    const auto t0 = std::chrono::steady_clock::now();
    const int coarsest = std::max(coarse_->min_depth(), coarse_->max_depth() - kCoarseDepthsAtOnce + 1);
    const int from =
        stroke_hidden ? std::max(coarse_->min_depth(), std::min(coarsest, kDeferredCoarseDepth)) : coarsest;
    const std::unordered_set<std::uint64_t> reach = coarse_reach(dims, changed);
    // With the stroke's tiles hidden, a group under one the frames drew within its bound waits (for
    // settle_coarse_levels): the frames do not need it, and would draw that one in its place while it waits.
    const auto parent_drawn = [&](std::uint64_t id) {
        if (!stroke_hidden || frames_drew_.empty() || tile_group_depth(id) == coarse_->max_depth()) return false;
        const std::size_t g = index_of(groups_, id);
        return g < groups_.size() && std::binary_search(frames_drew_.begin(), frames_drew_.end(), groups_[g].parent);
    };
    std::vector<std::uint64_t> ids, finer_ids;  // all to rebuild; those finer than the coarsest depths
    int read_from = coarsest;                   // the finest depth a level rebuilt now needs current
    // The coarsest depths' waiting levels are rebuilt wherever they are, not only within reach: a group there also
    // loses its level when its children change (a stroke's deferred tiles arriving), and nothing would draw or pick
    // its surface until it settles. Their coarse models hold every change already (read at once, below).
    for (const std::uint64_t id : coarse_stale_) {
        const int depth = tile_group_depth(id);
        if (depth >= from && coarse_->has_depth(depth) && (depth >= coarsest || reach.count(id) != 0) &&
            !parent_drawn(id)) {
            ids.push_back(id);
            if (depth < coarsest) finer_ids.push_back(id);
            read_from = std::min(read_from, depth);
        }
    }
    // Every change is read at once at the coarsest depths, and at a finer one only around the levels rebuilt there
    // (the changed tiles not read there since their last change: coarse_read_to_); settle_coarse_levels() re-reads
    // the rest at every depth (these rays again, finding nothing changed). A level rebuilt from a model without them
    // would stay wrong.
    for (const std::uint64_t t : changed) coarse_read_to_.erase(t);  // changed again: read at no depth yet
    read_coarse_at(changed, coarsest);
    if (!finer_ids.empty())
        read_coarse_at(unread_at(tiles_near_groups(groups_, finer_ids, coarse_changed_, dims), read_from), read_from);
    if (stroke_hidden) {
        const std::vector<std::uint64_t> wanted = wanted_finer_groups(dims, from);
        ids.insert(ids.end(), wanted.begin(), wanted.end());
    }
    if (!changed.empty()) detail_wanted_.clear();
    if (ids.empty()) return 0;
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    const std::size_t built = rebuild_coarse_levels(ids);
    lod_build_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return built;
}

std::vector<std::uint64_t> TileSurfaceCache::unread_at(const std::vector<std::uint64_t>& tiles, int depth) const {
    std::vector<std::uint64_t> out;
    out.reserve(tiles.size());
    for (const std::uint64_t t : tiles) {
        const auto it = coarse_read_to_.find(t);
        if (it == coarse_read_to_.end() || it->second > depth) out.push_back(t);
    }
    return out;
}

void TileSurfaceCache::read_coarse_at(const std::vector<std::uint64_t>& tiles, int depth) {
    if (tiles.empty()) return;
    coarse_->update(*coarse_model_, tiles, depth);  // the coarser depths find rays read there already
    for (const std::uint64_t t : tiles) {
        const auto [it, fresh] = coarse_read_to_.try_emplace(t, depth);
        if (!fresh) it->second = std::min(it->second, depth);
    }
}

void TileSurfaceCache::frames_drew(std::vector<std::uint64_t> group_ids) {
    if (group_ids.empty()) return;
    std::sort(group_ids.begin(), group_ids.end());
    group_ids.erase(std::unique(group_ids.begin(), group_ids.end()), group_ids.end());
    frames_drew_ = std::move(group_ids);
}

std::vector<std::uint64_t> TileSurfaceCache::wanted_finer_groups(const std::array<int, 3>& dims, int from) {
    std::vector<std::uint64_t> wanted = std::move(detail_wanted_);
    detail_wanted_.clear();
    std::sort(wanted.begin(), wanted.end());  // finest depth first (the depth is the id's top byte)
    std::vector<std::uint64_t> finer;
    int depth = from;
    for (const std::uint64_t id : wanted) {
        const std::size_t g = index_of(groups_, id);
        if (g == groups_.size()) continue;
        const int d = groups_[g].depth - 1;
        if (d < std::max(coarse_->min_depth(), kDeferredDetailDepth) || !coarse_->has_depth(d)) continue;
        for (const std::uint64_t c : groups_[g].children)
            if (coarse_stale_.count(c) != 0 && finer.size() < kDeferredDetailLevels) {
                finer.push_back(c);
                depth = std::min(depth, d);
            }
    }
    if (finer.empty()) return finer;
    const std::vector<std::uint64_t> tiles = unread_at(tiles_near_groups(groups_, finer, coarse_changed_, dims), depth);
    read_coarse_at(tiles, depth);
    return finer;
}

std::size_t TileSurfaceCache::settle_coarse_levels(std::chrono::steady_clock::time_point now, bool stroke_open,
                                                   const std::function<bool()>& yield) {
    if (coarse_stale_.empty()) return 0;
    const bool settled = now - coarse_changed_at_ >= group_settle_;
    if (!settled && !build_away_) return 0;
    const auto t0 = std::chrono::steady_clock::now();
    const auto slice_end = t0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                    std::chrono::duration<double>(kCoarseContourSliceS));
    // The slice ends early when the caller's work waits (yield), after at least one batch or level.
    const auto in_slice = [&] { return std::chrono::steady_clock::now() < slice_end && !(yield && yield()); };
    if (settled && !coarse_changed_.empty()) {
        // The finer coarse models follow the stroke's tiles between strokes, a slice a pass: during a stroke its
        // samples would wait for them, and the few levels a pass rebuilds would not repay it (the waiting groups'
        // children are drawn).
        if (stroke_open) return 0;
        std::size_t done = 0;
        do {
            const std::size_t n = std::min(kCoarseUpdateTiles, coarse_changed_.size() - done);
            coarse_->update(*coarse_model_, std::span<const std::uint64_t>(coarse_changed_).subspan(done, n));
            done += n;
        } while (done < coarse_changed_.size() && in_slice());
        for (std::size_t i = 0; i < done; ++i) coarse_read_to_.erase(coarse_changed_[i]);  // read at every depth
        coarse_changed_.erase(coarse_changed_.begin(), coarse_changed_.begin() + static_cast<std::ptrdiff_t>(done));
        if (!coarse_changed_.empty()) {  // levels are rebuilt once every changed tile is read
            lod_build_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            return 0;
        }
    }
    // Coarsest depth first: a frame descends from a group to its children only once none of their levels waits
    // (renderer::groups_standing_in), so the view refines a depth at a time.
    // Not settled (build_away_from_changes): only groups out of reach of the changed tiles, not re-read yet; their
    // reach is found again only after a change.
    if (!settled && away_reach_at_ != coarse_changed_at_) {  // coarse_changed_ only grows, with a change, until settled
        away_reach_ = coarse_reach(coarse_dims_, coarse_changed_);
        away_reach_at_ = coarse_changed_at_;
    }
    std::vector<std::uint64_t> ids;  // those whose depth is read (a coarse-first start-up reads the finer ones later)
    for (const std::uint64_t id : coarse_stale_)
        if (coarse_->has_depth(tile_group_depth(id)) && (settled || away_reach_.count(id) == 0)) ids.push_back(id);
    if (ids.empty()) return 0;
    std::sort(ids.begin(), ids.end(), [](std::uint64_t a, std::uint64_t b) {
        const int da = tile_group_depth(a), db = tile_group_depth(b);
        return da != db ? da > db : a < b;
    });
    // Start-up's finest groups (no stroke yet) in larger batches: nothing else waits for the sculpt thread then.
    const bool startup = coarse_changed_at_ == std::chrono::steady_clock::time_point{};
    const std::size_t budget = startup ? kCoarseStartupLevelsPerCollect : kCoarseLevelsPerCollect;
    // Levels that only read contoured coarse tiles first; then, within the slice and never during a stroke, those
    // that contour theirs (a depth read later, tile by tile as its levels need them).
    // Between strokes a depth is done before a finer one starts; during one, finer levels that only read come
    // meanwhile.
    std::vector<std::uint64_t> reads, contours;
    for (const std::uint64_t id : ids) {
        if (reads.size() >= budget) break;
        if (!stroke_open && !contours.empty() && tile_group_depth(id) < tile_group_depth(contours.front())) break;
        const std::size_t g = index_of(groups_, id);
        const bool read = g == groups_.size() || coarse_->contoured_around(groups_[g].depth, groups_[g].coords);
        (read ? reads : contours).push_back(id);  // a group gone is dropped by the rebuild
    }
    std::size_t built = rebuild_coarse_levels(reads);
    if (!stroke_open) {
        for (const std::uint64_t id : contours) {
            if (built >= budget) break;
            built += rebuild_coarse_levels({id});
            if (!in_slice()) break;
        }
    }
    lod_build_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return built;
}

std::size_t TileSurfaceCache::rebuild_coarse_levels(const std::vector<std::uint64_t>& ids) {
    std::vector<TileGroupSurface*> groups;
    std::vector<std::pair<int, std::array<int, 3>>> where;
    for (const std::uint64_t id : ids) {
        coarse_stale_.erase(id);
        const std::size_t g = index_of(groups_, id);
        if (g == groups_.size()) {  // gone
            estimated_.erase(id);
            missed_.erase(id);
            dropped_error_.erase(id);
            continue;
        }
        groups.push_back(&groups_[g]);
        where.emplace_back(groups_[g].depth, groups_[g].coords);
        missed_.erase(id);
    }
    coarse_->read_around(where);  // level() of these only reads from here on, so the jobs may run at once
    // A coarse-first start-up measures a level's error once all its group's tiles are in (update_startup_groups);
    // until then it keeps the level's estimate. A stroke's hidden tiles (defer_tiles) do not wait: the level is
    // measured against the group's tiles in now, so that frames keep choosing about the levels they chose before,
    // and again once they are all in.
    std::vector<bool> measure(groups.size(), true);
    if (!expected_.empty()) {
        for (std::size_t i = 0; i < groups.size(); ++i) {
            measure[i] = group_refined(*groups[i], true);
            if (group_refined(*groups[i])) provisional_.erase(groups[i]->id);
            else provisional_.insert(groups[i]->id);
            estimated_.erase(groups[i]->id);  // a new level: estimated again
        }
    }
    // A provisional level a change dropped: its error, which the new one keeps at least (the finest levels that
    // raised it may wait themselves now).
    std::vector<double> before(groups.size(), 0.0);
    for (std::size_t i = 0; i < groups.size(); ++i)
        if (const auto it = dropped_error_.find(groups[i]->id); it != dropped_error_.end()) {
            if (!measure[i]) before[i] = it->second;
            dropped_error_.erase(it);
        }
    std::vector<TileLodLevel> built(groups.size());
    std::vector<std::uint8_t> missed(groups.size(), 0);
    run_lod_jobs(groups.size(), [&](std::size_t i) {
        built[i] = coarse_->level(groups[i]->depth, groups[i]->coords);
        if (built[i].mesh.triangles.empty()) {
            // The model has surface in its box that the finest stride missed, and tiles of start-up or of a stroke
            // drawn coarse are not in to show it (a feature thinner than the stride: a bead, a fin).
            missed[i] = groups[i]->depth == coarse_->min_depth() && !group_refined(*groups[i]) &&
                        dexel_surface_in(*coarse_model_, group_cells(*groups[i]));
            return;
        }
        if (measure[i])
            built[i].error_m = coarse_level_error(*groups[i], built[i]);
        else if (groups[i]->depth == coarse_->min_depth())  // measured against the model's own surface points
            built[i].error_m = std::max(coarse_level_dexel_error(*groups[i], built[i]), before[i]);
        else  // the level's estimate is one coarse cell (CoarseLevelOptions::error_coarse_cells 1)
            built[i].error_m = std::max(built[i].error_m * kStartupErrorCoarseCells, before[i]);
    });
    for (std::size_t i = 0; i < groups.size(); ++i) {
        groups[i]->lods.clear();
        if (missed[i]) missed_.insert(groups[i]->id);
        if (!built[i].mesh.triangles.empty()) groups[i]->lods.push_back(std::move(built[i]));
        groups[i]->version = fresh_tile_version();
        groups[i]->levels_waiting = false;
    }
    coarse_->forget_reads();  // the levels hold what they need; a later rebuild reads its tiles again
    lod_groups_built_ += groups.size();
    return groups.size();
}

double TileSurfaceCache::coarse_level_error(const TileGroupSurface& group, const TileLodLevel& level) const {
    // Samples: each tile's six extreme vertices (a feature the coarse rays missed sticks out of it: an ear's tip),
    // and vertices spread evenly over the tiles, up to kSamples in all.
    // Depth-1 levels are drawn nearest the eye: 64 samples per tile there, 256 per group above.
    const std::size_t kSamples = group.depth == 1 ? 512 : 256;
    const int span = 1 << group.depth;
    std::vector<const TileSurface*> tiles;
    std::size_t vertices = 0;
    for (int z = group.coords[2] * span; z < (group.coords[2] + 1) * span && z < coarse_dims_[2]; ++z)
        for (int y = group.coords[1] * span; y < (group.coords[1] + 1) * span && y < coarse_dims_[1]; ++y)
            for (int x = group.coords[0] * span; x < (group.coords[0] + 1) * span && x < coarse_dims_[0]; ++x) {
                if (const TileSurface* t = find_by_id(tiles_, grid_index({x, y, z}, coarse_dims_))) {
                    tiles.push_back(t);
                    vertices += t->mesh.positions.size();
                }
            }
    TriangleGrid grid(level.mesh, 2.0 * lod_options_.cell_m * span);
    const std::size_t step = std::max<std::size_t>(1, vertices / kSamples);
    double worst = 0.0;
    std::size_t k = 0;
    for (const TileSurface* t : tiles) worst = sampled_distance(t->mesh.positions, grid, step, k, worst);
    return worst;
}

std::vector<std::uint64_t> TileSurfaceCache::missed_surface_groups() const {
    std::vector<std::uint64_t> ids;
    for (const std::uint64_t id : missed_) {
        const std::size_t g = index_of(groups_, id);
        if (g < groups_.size() && !groups_[g].children_cover && groups_[g].lods.empty()) ids.push_back(id);
    }
    std::sort(ids.begin(), ids.end());
    return ids;
}

double TileSurfaceCache::coarse_level_dexel_error(const TileGroupSurface& group, const TileLodLevel& level) const {
    // As many samples as coarse_level_error takes from the tiles at this depth.
    const std::size_t samples = group.depth == 1 ? 512 : 256;
    return dexel_surface_error(*coarse_model_, group_cells(group), level.mesh,
                               2.0 * lod_options_.cell_m * (1 << group.depth), samples);
}

std::optional<double> TileSurfaceCache::coarse_level_estimate(const TileGroupSurface& group,
                                                              const TileLodLevel& level) const {
    const int finest = coarse_->min_depth();
    // The finest depth's groups under this one, through the groups' children.
    std::vector<const TileGroupSurface*> under, walk{&group};
    double under_error = 0.0;  // the finest levels' own error (measured, or their start-up estimate)
    while (!walk.empty()) {
        const TileGroupSurface* g = walk.back();
        walk.pop_back();
        for (const std::uint64_t c : g->children) {
            const TileGroupSurface* child = find_by_id(groups_, c);
            if (!child) continue;
            if (child->depth > finest)
                walk.push_back(child);
            else
                under.push_back(child);
        }
    }
    // Samples (sampled_distance): each finest level's six extreme own corners (a thin feature the coarser rays
    // missed: an ear) and its own corners spread evenly, up to kSamples in all.
    constexpr std::size_t kSamples = 256;
    std::size_t vertices = 0;
    for (const TileGroupSurface* g : under) {
        if (coarse_stale_.count(g->id) != 0) return std::nullopt;  // its level waits
        if (!g->lods.empty()) vertices += 3 * g->lods.front().own_triangles;
    }
    TriangleGrid grid(level.mesh, 2.0 * lod_options_.cell_m * (1 << group.depth));
    const std::size_t step = std::max<std::size_t>(1, vertices / kSamples);
    double worst = 0.0;
    std::size_t k = 0;
    std::vector<Vec3> own;  // a level's own triangles' corners (not its ring and skirt)
    for (const TileGroupSurface* g : under) {
        if (g->lods.empty() || g->lods.front().own_triangles == 0) continue;
        under_error = std::max(under_error, g->lods.front().error_m);
        const TriMesh& m = g->lods.front().mesh;
        own.clear();
        for (std::size_t t = 0; t < g->lods.front().own_triangles; ++t)
            for (const std::uint32_t v : m.triangles[t]) own.push_back(m.positions[v]);
        worst = sampled_distance(own, grid, step, k, worst);
    }
    return worst + std::max(under_error, kStartupErrorCoarseCells * lod_options_.cell_m * (1 << finest));
}

}  // namespace tridex::compute
