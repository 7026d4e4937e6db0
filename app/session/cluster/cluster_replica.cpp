// app/session/cluster/cluster_replica.cpp - the replicated model: records applied, tiles contoured, viewports framed.
#include "app/session/cluster/cluster_replica.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "app/scene/session_spec.hpp"
#include "app/session/view/run_view.hpp"
#include "compute/contour/held_tiles.hpp"
#include "compute/contour/lod_worker.hpp"
#include "compute/contour/refine_wanted.hpp"
#include "compute/contour/sorted_ids.hpp"
#include "compute/model/model_digest.hpp"
#include "core/error.hpp"
#include "renderer/camera/off_axis.hpp"
#include "renderer/camera/scene_navigation.hpp"

namespace tridex::app {

ClusterReplica::ClusterReplica(const std::string& spec_json, const LodChoice& lod, const HelloMessage* late,
                               const ReplicaContour& how)
    : lod_(lod.on) {
    SessionSpec spec = spec_from_json(spec_json, "the session spec from rank 0");
    wp_ = prepare_session_workpiece(spec);
    compute::JournalApplyFrom from = replay_settings(spec);
    if (late) from.last_serial = late->last_closed_serial;
    applier_ = std::make_unique<compute::JournalApplier>(wp_.model, from);
    if (late) {  // the stream goes on from the snapshot the model was saved from
        if (!late->history.empty()) applier_->load_history(late->history);
        if (late->first_record > 0) applier_->resume_after(late->first_record - 1, late->prevs, late->first_record);
    }
    load_references(spec);
    stroke_changes_ = applier_->stroke_open();  // a late joiner resumed inside a push group
    contourer_ = std::make_unique<compute::Contourer>(wp_.model);
    if (lod_) {
        // As the session's sculpt thread does (SculptThread::use_tile_lod), before the first refresh queues every tile.
        compute::LodWorkerOptions o;
        o.lod.cell_m = wp_.model.lattice.cell_m;
        o.coarse_groups_from_cells = lod.coarse_groups_from_cells;
        tiles_.enable_lod(o.lod);
        const std::array<int, 3>& cells = wp_.model.lattice.cells;
        if (o.coarse_groups_from_cells > 0 && std::max({cells[0], cells[1], cells[2]}) >= o.coarse_groups_from_cells) {
            compute::CoarseLevelOptions levels;
            levels.max_depth = o.coarse_max_depth;
            tiles_.use_coarse_groups(wp_.model, levels, how.coarse_first);
            // The records change tiles in every frame of a stroke; no frame here holds its samples.
            tiles_.build_away_from_changes(true);
            if (how.coarse_first) {  // as SculptThread::arm_tile_lod; only the groups frames want are refined (no regions)
                const compute::Lattice& l = wp_.model.lattice;
                const Vec3 middle = l.to_world(Vec3(cells[0], cells[1], cells[2]) * 0.5);
                refiner_ = std::make_unique<compute::StartupRefiner>(wp_.model, std::min(levels.max_depth, 3), middle);
                tiles_.expect_tiles(refiner_->pending_tiles());
                o.startup_nice = o.nice;  // the groups stand in for the tiles' own levels; the tiles come first
                started_coarse_ = true;
            }
        }
        tiles_.build_lods_in_background(o);
    }
    update({}, false);
    // After the first refresh: the cache takes deferred tiles from then on.
    if (how.stroke_coarse && tiles_.coarse_groups()) {
        deferral_ = std::make_unique<compute::DeferredContour>(wp_.model.tiles.tiles);
        if (refiner_) refiner_->contour_beside(deferral_.get());
    }
}

ClusterReplica::~ClusterReplica() = default;

std::uint64_t ClusterReplica::digest() const { return compute::model_digest(wp_.model); }

std::optional<std::uint64_t> ClusterReplica::apply(const FrameMessage& m) {
    const std::span<const compute::JournalRecord> all(m.records);
    // A stroke open before or after the records: what they change is the stroke's (its close included).
    stroke_changes_ = stroke_changes_ || applier_->stroke_open();
    std::optional<std::uint64_t> mismatch;
    if (!m.check_digest) {
        applier_->apply(all);
    } else {
        applier_->apply(all.first(m.check_after));
        const std::uint64_t mine = digest();
        applier_->apply(all.subspan(m.check_after));
        if (mine != *m.check_digest) mismatch = mine;
    }
    stroke_changes_ = stroke_changes_ || applier_->stroke_open();
    return mismatch;
}

namespace {

// Which tiles `frusta` may see: each tile's lattice box grown by one cell (a tile's surface lies within its cells and
// the vertices it borrows from its neighbours within one cell of it).
std::vector<std::uint8_t> visible_tiles(const compute::TriDexel& model, std::span<const renderer::Frustum> frusta) {
    const compute::TileGrid& g = model.tiles;
    const compute::Lattice& l = model.lattice;
    constexpr int kT = compute::TileGrid::kTileCells;
    std::vector<std::uint8_t> visible(g.count(), 0);
    for (int tz = 0; tz < g.tiles[2]; ++tz)
        for (int ty = 0; ty < g.tiles[1]; ++ty)
            for (int tx = 0; tx < g.tiles[0]; ++tx) {
                const Vec3 lo(tx * kT - 1, ty * kT - 1, tz * kT - 1);
                const Vec3 hi(std::min((tx + 1) * kT, l.cells[0]) + 1, std::min((ty + 1) * kT, l.cells[1]) + 1,
                              std::min((tz + 1) * kT, l.cells[2]) + 1);
                const Aabb box{l.to_world(lo), l.to_world(hi)};
                for (const renderer::Frustum& f : frusta)
                    if (renderer::may_be_visible(f, box)) {
                        visible[g.index(tx, ty, tz)] = 1;
                        break;
                    }
            }
    return visible;
}

// The changed tiles no view needs yet: every group of changed tiles (26-connected) of which no tile is visible or
// next to a visible one, nor `must` (empty: none) or next to one. A group is contoured whole or not at all, because
// neighbouring tiles share the vertices on their border: a tile contoured beside a changed one left waiting would
// borrow vertices that are not there yet.
std::vector<std::uint32_t> waiting_tiles(const compute::TileGrid& g, const std::vector<std::uint8_t>& visible,
                                         const std::vector<std::uint8_t>& must) {
    std::vector<std::uint32_t> wait;
    std::vector<std::uint8_t> seen(g.count(), 0);
    std::vector<std::array<int, 3>> group, stack;
    for (int tz = 0; tz < g.tiles[2]; ++tz)
        for (int ty = 0; ty < g.tiles[1]; ++ty)
            for (int tx = 0; tx < g.tiles[0]; ++tx) {
                const std::size_t t0 = g.index(tx, ty, tz);
                if (!g.dirty[t0] || seen[t0]) continue;
                group.clear();
                stack.assign(1, {tx, ty, tz});
                seen[t0] = 1;
                bool needed = false;
                while (!stack.empty()) {
                    const std::array<int, 3> c = stack.back();
                    stack.pop_back();
                    group.push_back(c);
                    for (int dz = -1; dz <= 1; ++dz)
                        for (int dy = -1; dy <= 1; ++dy)
                            for (int dx = -1; dx <= 1; ++dx) {
                                const int x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
                                if (x < 0 || y < 0 || z < 0 || x >= g.tiles[0] || y >= g.tiles[1] || z >= g.tiles[2]) continue;
                                const std::size_t n = g.index(x, y, z);
                                needed |= visible[n] != 0 || (!must.empty() && must[n] != 0);
                                if (g.dirty[n] && !seen[n]) {
                                    seen[n] = 1;
                                    stack.push_back({x, y, z});
                                }
                            }
                }
                if (needed) continue;
                for (const std::array<int, 3>& c : group) wait.push_back(static_cast<std::uint32_t>(g.index(c[0], c[1], c[2])));
            }
    return wait;
}

// `visible` grown by one tile (each tile a view may see and its 26 neighbours).
std::vector<std::uint8_t> near_tiles(const compute::TileGrid& g, const std::vector<std::uint8_t>& visible) {
    std::vector<std::uint8_t> near(g.count(), 0);
    for (int tz = 0; tz < g.tiles[2]; ++tz)
        for (int ty = 0; ty < g.tiles[1]; ++ty)
            for (int tx = 0; tx < g.tiles[0]; ++tx) {
                if (!visible[g.index(tx, ty, tz)]) continue;
                for (int z = std::max(tz - 1, 0); z <= std::min(tz + 1, g.tiles[2] - 1); ++z)
                    for (int y = std::max(ty - 1, 0); y <= std::min(ty + 1, g.tiles[1] - 1); ++y)
                        for (int x = std::max(tx - 1, 0); x <= std::min(tx + 1, g.tiles[0] - 1); ++x)
                            near[g.index(x, y, z)] = 1;
            }
    return near;
}

// Whether a view may see a tile of group `id` (of `groups`, ascending by id), per `visible`.
bool group_seen(const std::vector<compute::TileGroupSurface>& groups, std::uint64_t id, const compute::TileGrid& g,
                const std::vector<std::uint8_t>& visible) {
    const compute::TileGroupSurface* group = compute::find_by_id(groups, id);
    if (!group) return false;
    const int span = 1 << group->depth;
    for (int z = group->coords[2] * span; z < std::min((group->coords[2] + 1) * span, g.tiles[2]); ++z)
        for (int y = group->coords[1] * span; y < std::min((group->coords[1] + 1) * span, g.tiles[1]); ++y)
            for (int x = group->coords[0] * span; x < std::min((group->coords[0] + 1) * span, g.tiles[0]); ++x)
                if (visible[g.index(x, y, z)]) return true;
    return false;
}

}  // namespace

void ClusterReplica::contour(std::span<const renderer::Frustum> frusta) { update(frusta, true); }

void ClusterReplica::update(std::span<const renderer::Frustum> frusta, bool refine) {
    compute::TileGrid& g = wp_.model.tiles;
    const bool stroke = deferral_ && std::exchange(stroke_changes_, false);
    const std::vector<std::uint64_t> wanted = wanted_.take();  // frames name them again
    if (stroke) {
        // A stroke drawn coarse: its changed tiles wait, hidden, and the refresh rebuilds the coarse levels over them.
        // Start-up's tiles among them stay start-up's too (it hides them and their neighbours until it contours them).
        const std::vector<std::uint64_t> changed = deferral_->defer(wp_.model);
        if (!changed.empty()) tiles_.defer_tiles(changed);
        stroke_deferred_ += changed.size();
    }
    // Deferred tiles among the changed ones or next to one are released (no tile contoured now borrows a vertex from
    // an old contour), and contoured now with their group of changed tiles, whatever the views: a released tile shows
    // its mesh, which must not be its contour from before the stroke. So no waiting tile lies next to a deferred one.
    std::vector<std::uint8_t> released;
    if (!stroke && deferral_) {
        std::vector<std::uint64_t> ids;
        if (deferral_->take_dirty(wp_.model, &ids) > 0) {
            released.assign(g.count(), 0);
            for (const std::uint64_t t : ids) released[t] = 1;
        }
    }
    const std::vector<std::uint8_t> visible =
        frusta.empty() ? std::vector<std::uint8_t>{} : visible_tiles(wp_.model, frusta);
    // Changed tiles no view needs yet wait; those contoured now that start-up has not contoured bring the start-up
    // tiles of the depth-1 groups they reach (StartupRefiner::contour_with_change), which may join a waiting group of
    // changed tiles to them: then it is contoured now too. Start-up's tiles in a group that waits stay start-up's.
    std::vector<std::uint32_t> wait;
    std::vector<std::uint8_t> handled(refiner_ ? g.count() : 0, 0);
    for (;;) {
        wait = frusta.empty() ? std::vector<std::uint32_t>{} : waiting_tiles(g, visible, released);
        if (!refiner_) break;
        std::vector<std::uint8_t> waits(g.count(), 0);
        for (const std::uint32_t t : wait) waits[t] = 1;
        std::vector<std::uint64_t> now;
        for (const std::uint32_t t : g.dirty_tiles())
            if (!waits[t] && !handled[t]) now.push_back(t);
        if (now.empty()) break;
        const std::vector<std::uint8_t> before(g.dirty.begin(), g.dirty.end());
        tiles_.stop_expecting(refiner_->pending_among(now));
        startup_refined_ += refiner_->contour_with_change(wp_.model, now);
        for (const std::uint64_t t : now) handled[t] = 1;
        for (const std::uint32_t t : g.dirty_tiles())  // those it brought: never asked to bring more
            if (before[t] == 0) handled[t] = 1;
    }
    // Waiting tiles are unmarked for this update (and the slice), and marked again after it.
    for (const std::uint32_t t : wait) g.dirty[t] = 0;
    contoured_ += contourer_->update(wp_.model);
    if (refine) refine_held(wanted, visible, stroke);
    for (const std::uint32_t t : wait) g.dirty[t] = compute::TileGrid::kWhole;  // its changed cells are not kept
    deferred_ = wait.size();
    if (deferral_) stroke_contoured_ += deferral_->take_released();
    refresh_tiles(wanted, stroke);
    if (lod_) tiles_.collect_lods();
    tile_view_of(tiles_.tiles(), tiles_.groups(), lod_, tile_view_);
}

void ClusterReplica::refine_held(const std::vector<std::uint64_t>& wanted, const std::vector<std::uint8_t>& visible,
                                 bool stroke) {
    // A coarse-first start-up reads one finer coarse depth first: frames draw its groups' levels where they need more
    // than the coarsest.
    if (started_coarse_ && tiles_.build_coarse_depth()) return;
    if (!refiner_ && (!deferral_ || deferral_->count() == 0)) return;
    const auto t0 = std::chrono::steady_clock::now();
    bool begun = false;
    const auto in_slice = [&] {
        const bool first = !std::exchange(begun, true);
        return first || std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < kStartupSliceS;
    };
    // Groups whose coarse reads missed a surface that start-up's or a stroke's tiles not yet in hold, where a view may
    // see one of their tiles, are contoured as if a frame wanted them.
    std::vector<std::uint64_t> ids = wanted;
    std::vector<std::uint64_t> missed = tiles_.missed_surface_groups();
    if (!visible.empty())
        std::erase_if(missed,
                      [&](std::uint64_t id) { return !group_seen(tiles_.groups(), id, wp_.model.tiles, visible); });
    compute::merge_ids(ids, missed);
    const compute::WantedRefined n =
        compute::refine_wanted_groups(ids, tiles_.groups(), wp_.model, *contourer_, refiner_.get(), deferral_.get(),
                                      compute::kWantedBlockDepth, in_slice);
    startup_refined_ += n.startup;
    contoured_ += n.startup + n.deferred;
    // Once the stroke closed, its deferred tiles a view may see (or next to one), oldest first; the others wait for a
    // view. A batch short of its size found every such tile.
    if (stroke || !deferral_ || deferral_->count() == 0) return;
    const std::vector<std::uint8_t> near = visible.empty() ? visible : near_tiles(wp_.model.tiles, visible);
    const auto seen = [&](std::uint64_t t) { return near.empty() || near[t] != 0; };
    constexpr std::size_t kBatch = compute::DeferredContour::kTilesPerBatch;
    while (in_slice()) {
        const std::size_t k = deferral_->contour_oldest_where(wp_.model, *contourer_, kBatch, seen);
        contoured_ += k;
        if (k < kBatch) break;
    }
}

void ClusterReplica::refresh_tiles(const std::vector<std::uint64_t>& wanted, bool stroke) {
    if (deferral_) {
        // While a stroke's tiles are hidden, the groups the frames drew over their bound get finer coarse levels, and
        // the waiting levels under the groups they drew within it are left for later.
        if (stroke) tiles_.want_detail(wanted);
        tiles_.frames_drew(drawn_.take());
    }
    compute::refresh_held_tiles(tiles_, *contourer_, refiner_.get(), deferral_.get());
    if (refiner_ && refiner_->done()) refiner_.reset();  // every tile is in
}

void ClusterReplica::want_detail(std::span<const std::uint64_t> group_ids) {
    if (refiner_ || deferral_) wanted_.offer(group_ids);
}

void ClusterReplica::frames_drew(std::span<const std::uint64_t> group_ids) {
    if (deferral_) drawn_.offer(group_ids);
}

void ClusterReplica::finish_contour() {
    if (started_coarse_)
        while (tiles_.build_coarse_depth()) {  // every coarse depth, as a start-up that ran to its end reads them
        }
    (void)wanted_.take();
    if (deferral_) deferral_->take_dirty(wp_.model);  // no changed tile borrows a vertex from an old contour
    contoured_ += contourer_->update(wp_.model);      // the changed tiles waiting for a view
    deferred_ = 0;
    if (refiner_) {
        const std::size_t n = refiner_->finish(wp_.model, *contourer_);
        startup_refined_ += n;
        contoured_ += n;
    }
    if (deferral_) {
        contoured_ += deferral_->contour_all(wp_.model, *contourer_);
        stroke_contoured_ += deferral_->take_released();
    }
    refresh_tiles({}, false);
    if (lod_) tiles_.collect_lods();
    tile_view_of(tiles_.tiles(), tiles_.groups(), lod_, tile_view_);
}

std::size_t ClusterReplica::stroke_tiles_waiting() const { return deferral_ ? deferral_->count() : 0; }

std::size_t ClusterReplica::startup_pending() const { return refiner_ ? refiner_->pending() : 0; }

std::size_t ClusterReplica::lod_pending() const { return lod_ ? tiles_.startup_lod_pending() : 0; }

void ClusterReplica::load_references(const SessionSpec& spec) {
    // Drawn, not felt: the meshes alone, no distance fields. A mesh this machine lacks leaves that object undrawn.
    reference_meshes_.reserve(spec.references.size());  // the objects point into it
    std::vector<const ReferenceSpec*> drawn;
    for (const ReferenceSpec& r : spec.references) {
        try {
            reference_meshes_.push_back(load_reference_mesh(r));
            drawn.push_back(&r);
        } catch (const Error& e) {
            reference_notes_.push_back("reference '" + r.name + "' not drawn here: " + e.what());
            std::fprintf(stderr, "tridex: %s\n", reference_notes_.back().c_str());
        }
    }
    for (std::size_t i = 0; i < drawn.size(); ++i)
        reference_objects_.push_back(reference_scene_object(*drawn[i], reference_meshes_[i]));
}

renderer::SceneView ClusterReplica::view(const FrameMessage& m) const {
    renderer::SceneView v;
    v.tiles = tile_view_.tiles;
    v.tile_groups = tile_view_.groups;
    v.lod = lod_;
    v.show_workspace = false;
    v.tool_shape = m.tool;
    v.tool_radius_m = m.show_tool ? m.tool.radius_m : 0.0;
    v.tool_centre_m = m.tool_m;
    v.tool_orientation = m.tool_orientation;
    v.occlusion_strength = m.ao;
    v.objects = reference_objects_;
    v.workpiece_pose = m.workpiece_pose;  // where rank 0 draws it (the scene's pose, or where the tool placed it)
    return v;
}

renderer::StereoCamera ClusterReplica::camera(const ClusterViewport& vp, const FrameMessage& m) {
    const renderer::SceneNavigation nav(m.nav_pose, m.nav_scale, std::min(1e-3, m.nav_scale), std::max(1e3, m.nav_scale));
    Pose head = m.head;
    double separation = m.eye_separation_m;
    if (vp.eye != ViewportEye::kBoth) {
        // One eye of a passive pair: a mono view from that eye.
        head.position = renderer::eye_positions(head, separation)[vp.eye == ViewportEye::kLeft ? 0 : 1];
        separation = 0.0;
    }
    const RunCamera c = navigated_camera(vp.screen, head, separation, nav);
    return renderer::StereoCamera{c.screen, c.head, c.eye_separation_m, c.near_m, c.far_m};
}

void ClusterReplica::diverge() {
    for (compute::RaySet& set : wp_.model.sets)
        for (std::vector<compute::Interval>& ray : set.rays)
            if (!ray.empty()) {
                ray[0].exit = std::nextafter(ray[0].exit, ray[0].exit + 1.0f);
                return;
            }
}

const compute::JournalApplyStats& ClusterReplica::applied() const { return applier_->stats(); }

}  // namespace tridex::app
