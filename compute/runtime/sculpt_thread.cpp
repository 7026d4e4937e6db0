// compute/runtime/sculpt_thread.cpp - the sculpt thread loop.
#include "compute/runtime/sculpt_thread.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <utility>

#include "compute/journal/journal_format.hpp"
#include "compute/runtime/gpu_contour_share.hpp"
#include "compute/runtime/active_surface_publish.hpp"
#include "compute/tools/sample_sweep.hpp"
#include "compute/tools/sweep.hpp"
#include "core/error.hpp"
#include "core/thread_name.hpp"

namespace tridex::app {

namespace {
// Re-centre the active surface when the tool has moved this many cells from the window centre,
// even without a model change (a window is ActiveSurface::kWindow rays wide).
constexpr double kRecentreCells = 4.0;
}  // namespace

SculptThread::SculptThread(compute::TriDexel& model, compute::Contourer& contourer, SpscRing<ToolSample>& samples,
                           TripleBuffer<ActiveSurface>& surface, const Vec3& start_m, double tool_radius_m,
                           double tool_span_m)
    : model_(model), own_backend_(make_cpu_backend(model)), backend_(own_backend_.get()), contourer_(contourer),
      samples_(samples), surface_(surface), published_centre_m_(start_m) {
    if (!is_finite(start_m)) throw Error("SculptThread: start position is not finite");
    if (!std::isfinite(tool_radius_m) || tool_radius_m < 0.0 || !std::isfinite(tool_span_m) || tool_span_m < 0.0)
        throw Error("SculptThread: tool_radius_m and tool_span_m must be finite and >= 0");
    tool_radius_m_ = tool_radius_m;
    tool_span_m_ = tool_span_m;
    publish(start_m);
}

SculptThread::~SculptThread() {
    try {
        stop();
    } catch (...) {
        // A failure nobody collected with stop(): the thread is joined; a destructor must not throw.
    }
}

void SculptThread::use_mesh_tools(std::vector<std::shared_ptr<const compute::MeshTool>> tools) {
    if (thread_.joinable()) throw Error("SculptThread::use_mesh_tools: call it before start()");
    mesh_tools_ = std::move(tools);
    mirrored_mesh_tools_.assign(mesh_tools_.size(), nullptr);
}

std::shared_ptr<const compute::MeshTool> SculptThread::mirrored_mesh_tool(std::uint32_t id) {
    const std::shared_ptr<const compute::MeshTool> tool = mesh_tool(id);
    if (!mirrored_mesh_tools_[id]) mirrored_mesh_tools_[id] = compute::mirrored_mesh_tool(*tool);
    return mirrored_mesh_tools_[id];
}

std::shared_ptr<const compute::MeshTool> SculptThread::mesh_tool(std::uint32_t id) const {
    if (id >= mesh_tools_.size())
        throw Error("tool sample: mesh tool " + std::to_string(id) + " is not in the session's table of " +
                    std::to_string(mesh_tools_.size()));
    return mesh_tools_[id];
}

void SculptThread::use_backend(BooleanBackend& backend) {
    if (thread_.joinable()) throw Error("SculptThread::use_backend: call it before start()");
    backend_ = &backend;
}

void SculptThread::use_journal(compute::JournalWriter& journal) {
    if (thread_.joinable()) throw Error("SculptThread::use_journal: call it before start()");
    journal_ = &journal;
    drained_.reserve(samples_.capacity() + 1);
}

void SculptThread::use_stream(compute::ToolStreamSink& stream) {
    if (thread_.joinable()) throw Error("SculptThread::use_stream: call it before start()");
    streams_.push_back(&stream);
    drained_.reserve(samples_.capacity() + 1);
}

void SculptThread::use_gpu_contour(GpuContourShare& share) {
    if (thread_.joinable()) throw Error("SculptThread::use_gpu_contour: call it before start()");
    gpu_contour_ = &share;
    if (tile_cache_.lod_enabled()) share.read_back_tiles();  // the levels are built from the contour read back
}

void SculptThread::set_history_budget(std::size_t bytes) {
    if (thread_.joinable()) throw Error("SculptThread::set_history_budget: call it before start()");
    if (bytes == 0) throw Error("SculptThread::set_history_budget: the budget must be > 0 bytes");
    history_budget_ = bytes;
}

void SculptThread::remove_islands(bool on) {
    if (thread_.joinable()) throw Error("SculptThread::remove_islands: call it before start()");
    remove_islands_ = on;
}

void SculptThread::strokes_end_on_release(bool on) {
    if (thread_.joinable()) throw Error("SculptThread::strokes_end_on_release: call it before start()");
    idle_close_ = !on;
}

void SculptThread::use_checkpoints(std::function<CheckpointFile(const compute::TriDexel&)> write, double interval_s) {
    if (thread_.joinable()) throw Error("SculptThread::use_checkpoints: call it before start()");
    if (!std::isfinite(interval_s) || interval_s <= 0.0)
        throw Error("SculptThread::use_checkpoints: interval_s must be finite and > 0, got " + std::to_string(interval_s));
    checkpoint_write_ = std::move(write);
    checkpoint_interval_s_ = interval_s;
}

bool SculptThread::request(SculptRequest r) { return requests_.try_push(r); }

void SculptThread::follow_marks(std::vector<SculptMark> marks) {
    if (thread_.joinable()) throw Error("SculptThread::follow_marks: call it before start()");
    for (std::size_t k = 0; k < marks.size(); ++k) {
        if (marks[k].request == SculptRequest::kSave)
            throw Error("SculptThread::follow_marks: mark " + std::to_string(k) + " is a save, which changes no stroke");
        if (k > 0 && marks[k].after_samples < marks[k - 1].after_samples)
            throw Error("SculptThread::follow_marks: mark " + std::to_string(k) + " comes after " +
                        std::to_string(marks[k].after_samples) + " samples, before the mark ahead of it (" +
                        std::to_string(marks[k - 1].after_samples) + ")");
    }
    follow_ = std::move(marks);
    next_mark_ = 0;
    following_ = true;
}

void SculptThread::use_saver(std::function<std::string(const compute::TriDexel&)> save) {
    if (thread_.joinable()) throw Error("SculptThread::use_saver: call it before start()");
    saver_ = std::move(save);
}

void SculptThread::observe_surface(std::function<void(const ActiveSurface&)> observer) {
    if (thread_.joinable()) throw Error("SculptThread::observe_surface: call it before start()");
    surface_observer_ = std::move(observer);
    if (surface_observer_) publish(published_centre_m_);  // the observer starts from a snapshot of its own
}

SculptLive SculptThread::live() const {
    std::lock_guard<std::mutex> lock(live_mutex_);
    return live_;
}

SaveStatus SculptThread::save_status() const {
    std::lock_guard<std::mutex> lock(save_mutex_);
    return save_status_;
}

void SculptThread::start() {
    if (thread_.joinable()) throw Error("SculptThread::start: already running");
    history_ = std::make_unique<SculptHistory>(model_, *backend_, history_budget_);
    history_->remove_islands(remove_islands_);
    if (follow_start_) {  // joined late: the host's strokes so far, to follow its undos and redos of them
        history_->load_steps(follow_start_->history);
        for (const ToolSample& p : follow_start_->prevs) sites_.sweeps().set_prev(p);
        last_closed_serial_ = follow_start_->last_closed_serial;
        follow_start_.reset();
    }
    checkpoint_last_ = std::chrono::steady_clock::now();
    stop_.store(false);
    failure_ = nullptr;
    thread_ = std::thread([this] {
        name_this_thread("tridex-sculpt");
        run();
    });
}

void SculptThread::stop() {
    if (!thread_.joinable()) {
        if ((refiner_ || deferral_) && !failure_) refine_startup(true);  // never started: contour every tile
        return;
    }
    stop_.store(true);
    thread_.join();
    if (failure_) std::rethrow_exception(std::exchange(failure_, nullptr));
}

void SculptThread::run() {
    for (;;) {
        const bool stopping = stop_.load(std::memory_order_acquire);
        bool worked = false;
        const std::uint64_t steps_before = stats_.steps;
        if (failure_) {  // failed earlier: keep the ring drained so the producer never sees it full
            ToolSample s;
            while (pop_sample(s)) worked = true;
        } else {
            try {
                const auto t0 = std::chrono::steady_clock::now();
                worked = step();
                if (ask_out_) serve_snapshot_asks();
                if (worked) stats_.busy_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            } catch (...) {
                failure_ = std::current_exception();
                worked = true;
            }
        }
        if (!failure_) {
            try {
                // Start-up's refinement waits while the model changes: a stroke's own tiles are contoured at once.
                if (stats_.steps == steps_before || (stopping && !worked)) refine_startup(stopping && !worked);
                collect_lods();
                publish_mesh_if_due(stopping && !worked);  // the last state always reaches the renderer
            } catch (...) {
                failure_ = std::current_exception();
            }
        }
        if (checkpoint_write_ && !failure_) checkpoint_if_due();
        note_persistence();
        if (journal_) {
            const auto t0 = std::chrono::steady_clock::now();
            if (stopping && !worked)
                journal_->sync();  // everything applied is durable when the thread ends
            else
                journal_->sync_if_due();
            stats_.busy_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        }
        if (stopping && !worked) {  // the ring was drained after stop was asked
            if (!failure_) {
                try {
                    close_stroke();  // the last stroke is a step too
                    take_held_requests();  // asked during a drag the session ended in
                    // Its close's change (deferred as its steps were) reaches the contour and the renderer too.
                    if (deferral_ && deferral_->count() > 0) refine_startup(true);
                    publish_mesh_if_due(true);
                } catch (...) {
                    failure_ = std::current_exception();
                }
            }
            stats_.held_requests_dropped += held_requests_.size();  // after a failure nothing is taken
            held_requests_.clear();
            if (journal_) journal_->sync();
            stats_.history = history_->stats();
            return;
        }
        if (worked) {
            const compute::HistoryStats h = history_->stats();
            std::lock_guard<std::mutex> lock(live_mutex_);
            live_.history_bytes = h.bytes;
            live_.history_budget_bytes = h.budget_bytes;
            live_.undo_times = undo_clock_.times(history_->next_undo_serial(), history_->next_redo_serial(),
                                                 history_->stroke_open() && stroke_changed_);
        }
        passes_.fetch_add(1, std::memory_order_release);
        if (!worked) std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
}

bool SculptThread::cut_waiting() {
    if (requests_.size() > 0) return true;
    ToolSample s;
    while (!carried_cut_ && samples_.try_pop(s)) {
        carried_.push_back(s);
        carried_cut_ = s.op != ToolOp::kNone && s.tool.radius_m > 0.0;
    }
    return carried_cut_;
}

bool SculptThread::pop_sample(ToolSample& s) {
    if (carried_next_ < carried_.size()) {
        s = carried_[carried_next_++];
        if (carried_next_ == carried_.size()) {
            carried_.clear();
            carried_next_ = 0;
            carried_cut_ = false;
        }
        return true;
    }
    return samples_.try_pop(s);
}

void SculptThread::flush(std::size_t begin, std::size_t end, bool& changed) {
    if (!batch_.empty()) {
        if (!history_->stroke_open()) {  // a stroke opens: its idle clock starts
            last_change_t_s_ = open_t_s();
            sites_.opened();
        }
        push_stroke_ = batch_.back().op == ToolOp::kPush;  // a batch belongs to one stroke (step splits at closes)
        const compute::BooleanStats b = history_->apply(batch_);
        stats_.booleans += batch_.size();
        stats_.rays_changed += b.rays_changed;
        if (b.rays_changed > 0) {
            undo_clock_.changed(stats_.samples);
            changed = true;
            stroke_changed_ = true;
            changed_since_checkpoint_ = true;
            last_change_t_s_ = open_t_s();
        }
        batch_.clear();
    }
    if (journal_ && end > begin) journal_->append(std::span<const ToolSample>(drained_).subspan(begin, end - begin));
    if (end > begin)
        for (compute::ToolStreamSink* s : streams_) {
            s->append(std::span<const ToolSample>(drained_).subspan(begin, end - begin));
            s->after_record(model_);
        }
}

void SculptThread::record_mark(std::uint32_t type, std::uint64_t serial, std::uint64_t rays) {
    if (journal_) journal_->mark(type, serial, rays);
    for (compute::ToolStreamSink* s : streams_) {
        s->mark(type, serial, rays);
        s->after_record(model_);
    }
}

double SculptThread::contour_changed(const std::chrono::steady_clock::time_point& t0,
                                     const std::chrono::steady_clock::time_point& t1, bool stroke_tail) {
    if (gpu_contour_) {
        stats_.tiles_recontoured += gpu_contour_->update_dirty(model_.tiles);
        model_.clear_dirty();
    } else {
        if (deferral_ && mesh_out_ && mesh_form_ == MeshForm::kTiles && (history_->stroke_open() || stroke_tail)) {
            // A stroke drawn coarse: its tiles wait, hidden; the coarse levels over them are rebuilt with the publish.
            // Its tail (the change its close makes) too: contouring the deferred tiles beside it would hold the
            // samples of the next stroke.
            // Start-up's tiles among them stay the refinement's too (it hides them and their neighbours until it has
            // contoured them), so no tile is drawn beside one never contoured.
            const std::vector<std::uint64_t> changed = deferral_->defer(model_);
            tile_cache_.defer_tiles(changed);
            stats_.tiles_deferred += changed.size();
        } else {
            // A coarse-first start-up: the tiles of the depth-1 groups the change reaches are contoured with it, so it
            // is drawn at full resolution (StartupRefiner::contour_with_change); those it changed before their first
            // contour are a stroke's, not start-up's.
            if (refiner_ && !refiner_->done()) {
                const std::vector<std::uint32_t> d = model_.tiles.dirty_tiles();
                const std::vector<std::uint64_t> dirty(d.begin(), d.end());
                tile_cache_.stop_expecting(refiner_->pending_among(dirty));
                stats_.startup_tiles_refined += refiner_->contour_with_change(model_, dirty);
            }
            // Deferred tiles the change reaches are contoured with it: no tile borrows a vertex from an old contour.
            if (deferral_) deferral_->take_dirty(model_);
            stats_.tiles_recontoured += contourer_.update(model_);
        }
    }
    ++stats_.steps;
    const auto t2 = std::chrono::steady_clock::now();
    const double contour_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
    stats_.boolean_ms.add(std::chrono::duration<double, std::milli>(t1 - t0).count());
    stats_.contour_ms.add(contour_ms);
    {
        std::lock_guard<std::mutex> lock(live_mutex_);
        live_.steps = stats_.steps;
        live_.step_ms.add(std::chrono::duration<double, std::milli>(t2 - t0).count());
    }
    mesh_pending_ = mesh_out_ != nullptr;
    return contour_ms;
}

bool SculptThread::step() {
    bool any = take_requests();
    const auto t0 = std::chrono::steady_clock::now();
    ToolSample s;
    StepWork w;
    bool sampled = false;
    batch_.clear();
    drained_.clear();
    any |= take_marks(w);
    while (pop_sample(s)) {
        take_marks(w);  // a recorded request that came after the samples drained so far
        sampled = true;
        if (follower_) forward_own(s);  // a joiner's own tool: to the host, whose stream carves it here
        else take_sample(s, w);
    }
    if (!own_.empty()) {
        outlet_.samples(own_);
        own_.clear();
    }
    any |= take_sites(w, sampled);
    if (!sampled) return any;
    flush(w.begin, w.n, w.changed);
    // The tool left the material: nothing changed for kStrokeIdleS of device time (the open stroke's site's clock).
    if (idle_close_ && !following_ && history_->stroke_open() && open_t_s() - last_change_t_s_ >= kStrokeIdleS)
        take(SculptRequest::kEndStroke, sites_.sweeps().open_site());  // recorded: when depends on the batching
    // Haptics first: publish the changed surface before contouring, which only the renderer needs.
    // The window follows the god-object (ToolSample::surface_m), not the HIP, so a hand pushed deep into
    // material does not drag the window away from the proxy it constrains, until the HIP leaves what that
    // window covers (ActiveSurface::window_centre_m). (Widening the window to cover the HIP too was tried: the
    // coarser stride then hides thin walls, and the proxy ends inside material far more often;
    // tests/stress/test_stress_haptics.cpp measures both.) It follows this site's own tool only.
    const Vec3 centre = !have_prev_ ? published_centre_m_ : ActiveSurface::window_centre_m(
        prev_.surface_m, prev_.position, 0.5 * compute::tool_extent_m(tool_span_m_, tool_reach_m(prev_.tool)),
        compute::kDefaultMotionMarginM, model_.lattice.cell_m);
    const double moved_cells = glm::length(centre - published_centre_m_) / model_.lattice.cell_m;
    // A push stroke keeps the haptic surface of its start (holding_reference); it is re-extracted there only to follow
    // the tool.
    if ((w.changed && !holding_reference()) || moved_cells > kRecentreCells) publish(centre);
    if (w.changed) {
        pending_sample_.keep_older(w.oldest_cut);
        contour_changed(t0, std::chrono::steady_clock::now());
    }
    return true;
}

void SculptThread::note_persistence() {
    const std::string journal_error = journal_ ? journal_->error() : std::string();
    const bool journal_failed = !journal_error.empty();
    const bool checkpoint_failed = !stats_.checkpoint_error.empty();
    if (journal_failed == journal_noted_ && checkpoint_failed == checkpoint_noted_) return;
    std::lock_guard<std::mutex> lock(save_mutex_);
    if (journal_failed) save_status_.journal_error = journal_error;
    if (checkpoint_failed) save_status_.checkpoint_error = stats_.checkpoint_error;
    journal_noted_ = journal_failed;
    checkpoint_noted_ = checkpoint_failed;
}

void SculptThread::checkpoint_if_due() {
    if (!changed_since_checkpoint_ || !stats_.checkpoint_error.empty() || history_->stroke_open()) return;
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - checkpoint_last_).count() < checkpoint_interval_s_) return;
    checkpoint_last_ = now;
    try {
        const CheckpointFile f = checkpoint_write_(model_);
        changed_since_checkpoint_ = false;
        ++stats_.checkpoints;
        if (journal_) journal_->checkpoint(f.name, f.bytes, f.crc);
    } catch (const std::exception& e) {
        stats_.checkpoint_error = e.what();
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - now).count();
    stats_.checkpoint_ms_total += ms;
    stats_.busy_ms += ms;
}

void SculptThread::publish_mesh_to(TripleBuffer<MeshFrame>& out, double min_interval_s, MeshForm form,
                                   ChangeSignal* sculpted) {
    if (thread_.joinable()) throw Error("SculptThread::publish_mesh_to: call it before start()");
    if (!std::isfinite(min_interval_s) || min_interval_s < 0.0)
        throw Error("SculptThread::publish_mesh_to: min_interval_s must be finite and >= 0, got " +
                    std::to_string(min_interval_s));
    mesh_out_ = &out;
    mesh_interval_s_ = min_interval_s;
    mesh_form_ = form;
    mesh_sculpted_ = sculpted;
    publish_mesh();
}

namespace {

// Makes `shared` hold a shared copy of every item of `items`, reusing the copy already in `shared` of each item whose
// (id, version) is unchanged: both lists are ordered by id.
template <typename T>
void share_unchanged(const std::vector<T>& items, std::vector<std::shared_ptr<const T>>& shared) {
    std::vector<std::shared_ptr<const T>> next;
    next.reserve(items.size());
    std::size_t k = 0;
    for (const T& item : items) {
        while (k < shared.size() && shared[k]->id < item.id) ++k;
        if (k < shared.size() && shared[k]->id == item.id && shared[k]->version == item.version)
            next.push_back(shared[k]);
        else
            next.push_back(std::make_shared<const T>(item));
    }
    shared = std::move(next);
}

}  // namespace

void SculptThread::share_tile_cache(MeshFrame& slot) {
    stats_.lod_tiles_built = tile_cache_.lod_tiles_built();
    stats_.lod_groups_built = tile_cache_.lod_groups_built();
    stats_.lod_build_ms = tile_cache_.lod_build_ms();
    stats_.lod_discarded = tile_cache_.lod_discarded();
    stats_.lod_latency_ms = tile_cache_.lod_latency_ms();
    stats_.lod_pending = tile_cache_.lod_pending();
    share_unchanged(tile_cache_.tiles(), shared_tiles_);
    share_unchanged(tile_cache_.groups(), shared_groups_);
    std::size_t triangles = 0;
    for (const compute::TileSurface& t : tile_cache_.tiles()) triangles += t.mesh.triangles.size();
    slot.groups = shared_groups_;
    slot.tiles = shared_tiles_;
    slot.triangles = triangles;
}

void SculptThread::publish_mesh() {
    const auto t0 = std::chrono::steady_clock::now();
    MeshFrame& slot = mesh_out_->back();
    slot.gpu = gpu_contour_ != nullptr;
    if (gpu_contour_) {  // the surface is in the GPU buffers: announce the change, and its tiles' levels of detail
        slot.mesh = TriMesh{};
        slot.materials.clear();
        slot.tiles.clear();
        slot.groups.clear();
        if (tile_cache_.lod_enabled()) {
            gpu_contour_->refresh_tiles(tile_cache_);
            share_tile_cache(slot);
        }
        slot.tiled = true;
        slot.triangles = 0;  // the render thread counts the GPU contour's triangles itself
    } else if (mesh_form_ == MeshForm::kWhole) {
        slot.mesh = contourer_.mesh();
        slot.materials = contourer_.mesh_materials();
        slot.tiles.clear();
        slot.groups.clear();
        slot.tiled = false;
        slot.triangles = slot.mesh.triangles.size();
    } else {
        refresh_tile_cache();
        share_tile_cache(slot);
        slot.mesh = TriMesh{};
        slot.materials.clear();
        slot.tiled = true;
    }
    slot.sculpt_steps = stats_.steps;
    slot.published_s = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    // A version the renderer never took is replaced unseen: its changes are first drawn with this one, so this
    // one carries its oldest sample.
    if (mesh_out_->unread()) pending_sample_.keep_older(last_oldest_sample_);
    const bool sampled = std::isfinite(pending_sample_.made_s);
    slot.oldest_sample_s = sampled ? pending_sample_.made_s : std::numeric_limits<double>::quiet_NaN();
    slot.oldest_sample_t_s = sampled ? pending_sample_.t_s : std::numeric_limits<double>::quiet_NaN();
    last_oldest_sample_ = std::exchange(pending_sample_, SampleTimes{});
    slot.version = ++mesh_version_;
    if (!refiner_ && stats_.startup_refined_s < 0.0) stats_.startup_refined_s = slot.published_s;
    mesh_out_->publish();
    if (sampled && mesh_sculpted_) mesh_sculpted_->notify();
    mesh_pending_ = false;
    mesh_last_ = std::chrono::steady_clock::now();
    ++stats_.mesh_publishes;
    stats_.mesh_publish_ms.add(std::chrono::duration<double, std::milli>(mesh_last_ - t0).count());
}

void SculptThread::publish_mesh_if_due(bool force) {
    if (!mesh_pending_) return;
    const double since_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - mesh_last_).count();
    // A sculpted change goes out at once while the renderer has taken the last publish: the hand waits for it.
    const bool sculpted = std::isfinite(pending_sample_.made_s) && !mesh_out_->unread();
    // Background work's mesh (refined or deferred tiles, levels) waits for a cut's pass, which publishes it too; for
    // at most kBackgroundPublishWaitS (a tool held cutting in air never changes the model).
    if (!force && !sculpted && since_s < kBackgroundPublishWaitS && !stop_.load(std::memory_order_acquire) &&
        cut_waiting()) {
        ++stats_.background_yields;
        return;
    }
    if (force || sculpted || since_s >= mesh_interval_s_) publish_mesh();
}

void SculptThread::publish(const Vec3& centre_m) {
    const double extent_m = compute::tool_extent_m(tool_span_m_, have_prev_ ? tool_reach_m(prev_.tool) : tool_radius_m_);
    if (holding_reference())
        history_->read_stroke_start([&](const compute::TriDexel& reference) {
            compute::extract_active_surface(reference, centre_m, extent_m, ++sequence_, surface_.back());
        });
    else
        compute::extract_active_surface(model_, centre_m, extent_m, ++sequence_, surface_.back());
    // Every sample drained so far is in the model (a push stroke's reference lacks its own pushes, never a cut).
    surface_.back().applied_made_s = have_prev_ ? prev_.made_s : -std::numeric_limits<double>::infinity();
    if (surface_observer_) surface_observer_(surface_.back());
    surface_.publish();
    published_centre_m_ = centre_m;
    ++stats_.publishes;
}

}  // namespace tridex::app
