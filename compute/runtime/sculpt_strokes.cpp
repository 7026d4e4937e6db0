// compute/runtime/sculpt_strokes.cpp - the sculpt thread's samples, strokes and requests: its own tool's and other
// sites' (a shared session), undo and redo, and the marks a replay follows.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <utility>

#include "compute/journal/journal_format.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "compute/tools/symmetry.hpp"
#include "core/error.hpp"

namespace tridex::app {

namespace {
// The sample's tool carves (an op and a tool with a size).
bool tool_cuts(const ToolSample& s) { return s.op != ToolOp::kNone && s.tool.radius_m > 0.0; }
// A request a joiner takes itself rather than sending it to the host.
bool local_request(SculptRequest r) {
    return r == SculptRequest::kSave || r == SculptRequest::kFiner || r == SculptRequest::kCoarser;
}
}  // namespace

void SculptThread::use_site_intake(SiteIntake& intake) {
    if (thread_.joinable()) throw Error("SculptThread::use_site_intake: call it before start()");
    intake_ = &intake;
}

void SculptThread::observe_refusals(std::function<void(const SculptRefusal&)> observer) {
    if (thread_.joinable()) throw Error("SculptThread::observe_refusals: call it before start()");
    refusal_observer_ = std::move(observer);
}

double SculptThread::open_t_s() const {
    const ToolSample* p = sites_.sweeps().prev(sites_.sweeps().open_site());
    return p ? p->t_s : prev_.t_s;
}

void SculptThread::take_sample(const ToolSample& s, StepWork& w) {
    ++stats_.samples;
    if (journal_ || !streams_.empty()) drained_.push_back(s);
    const bool cuts = tool_cuts(s);
    if (cuts) w.oldest_cut.keep_older({s.made_s, s.t_s});
    // A stroke closes where the tool stops cutting or changes what it does, or another site's tool cuts; the sweep
    // ending at `s` then belongs to the next stroke.
    compute::SiteSweeps& sites = sites_.sweeps();
    const compute::StrokeClose close = sites.closes_before(s, history_->stroke_open() || !batch_.empty());
    if (close != compute::StrokeClose::kNo) {
        flush(w.begin, w.n, w.changed);
        w.begin = w.n;
        close_stroke(close == compute::StrokeClose::kSiteSwitch ? std::optional<std::uint8_t>(s.site) : std::nullopt);
    }
    // The local tool stopped cutting: the requests asked during its drag are taken here, after the drag.
    // (A joiner's own samples come back from the host as echoes: its release is seen in forward_own instead.)
    if (!follower_ && !held_requests_.empty() && s.site == local_site_ && !cuts) {
        flush(w.begin, w.n, w.changed);
        w.begin = w.n;
        take_held_requests();
    }
    const bool mesh = cuts && sites.prev(s.site) && s.tool.kind == ToolKind::kMesh;
    const bool mirror = mesh && s.symmetry.mirrors != 0;
    sites.advance(s, mesh ? mesh_tool(s.tool.mesh_id) : nullptr, mirror ? mirrored_mesh_tool(s.tool.mesh_id) : nullptr,
                  compute::symmetry_centre(model_.lattice), model_.lattice.cell_m, batch_);
    if (s.site == local_site_ && !follower_) {
        prev_ = s;
        have_prev_ = true;
    }
    ++w.n;
}

bool SculptThread::take_sites(StepWork& w, bool& sampled) {
    if (!intake_) return false;
    site_entries_.clear();
    if (intake_->drain(site_entries_) == 0) return false;
    for (const SiteEntry& e : site_entries_) {
        if (e.kind == SiteEntry::kSample) {
            take_sample(e.sample, w);
            ++stats_.site_samples;
            sampled = true;
            continue;
        }
        flush(w.begin, w.n, w.changed);  // the samples before a request or mark go first
        w.begin = w.n;
        if (e.kind == SiteEntry::kMark) follow_mark(e);
        else if (e.kind == SiteEntry::kCheck) follow_check(e.serial);
        else if (e.kind == SiteEntry::kSnapshot) take_snapshot(e.site);
        else take(e.request, e.site);
    }
    return true;
}

bool SculptThread::take_requests() {
    SculptRequest r;
    bool any = false;
    while (requests_.try_pop(r)) {
        any = true;
        if (holds_request(r)) {
            if (held_requests_.size() < kMaxHeldRequests) {
                held_requests_.push_back(r);
                ++stats_.held_requests;
                held_count_.store(held_requests_.size(), std::memory_order_release);
            } else {
                ++stats_.held_requests_dropped;
            }
        } else if (follower_ && !local_request(r)) {
            outlet_.request(r);  // the host decides; its marks come back
        } else {
            take(r, local_site_);
        }
    }
    return any;
}

bool SculptThread::holds_request(SculptRequest r) const {
    if (idle_close_) return false;
    if (!held_requests_.empty()) return true;  // every request after a held one waits behind it, in order
    if (r != SculptRequest::kUndo && r != SculptRequest::kRedo) return false;
    return have_prev_ && tool_cuts(prev_);
}

void SculptThread::take_held_requests() {
    std::vector<SculptRequest> held;
    held.swap(held_requests_);
    held_count_.store(0, std::memory_order_release);
    if (held.empty()) return;
    // A joiner's go to the host after its samples up to the release, in their order; its saves and coarseness
    // changes are its own.
    if (follower_ && !own_.empty()) {
        outlet_.samples(own_);
        own_.clear();
    }
    for (const SculptRequest r : held) {
        if (follower_ && !local_request(r))
            outlet_.request(r);
        else
            take(r, local_site_);
    }
}

void SculptThread::save_now() {
    const auto t0 = std::chrono::steady_clock::now();
    std::string line;
    bool ok = false;
    try {
        if (!saver_) throw Error("no save file for this session");
        line = saver_(model_);
        ok = true;
    } catch (const std::exception& e) {
        line = e.what();
    }
    stats_.busy_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::lock_guard<std::mutex> lock(save_mutex_);
    ++(ok ? save_status_.saves : save_status_.failures);
    save_status_.message = line;
    save_status_.ok = ok;
}

void SculptThread::refuse(SculptRequest r, std::uint8_t site, std::uint8_t by_site, std::uint64_t serial) {
    const SculptRefusal refusal{r, site, by_site, serial};
    stats_.refusals.push_back(refusal);
    if (refusal_observer_) refusal_observer_(refusal);
}

void SculptThread::take(SculptRequest r, std::uint8_t site) {
    if (r == SculptRequest::kSave) {
        save_now();
        return;
    }
    if (r == SculptRequest::kFiner || r == SculptRequest::kCoarser) {
        change_coarseness(r, site);
        return;
    }
    if (site == local_site_) stats_.marks.push_back({stats_.samples, r});
    // Another site's open stroke is theirs to end; an undo or redo splits it (their gesture goes on), and what it
    // changed so far then stands in the way like any later stroke.
    const bool others_open = history_->stroke_open() && sites_.sweeps().open_site() != site;
    if (r == SculptRequest::kEndStroke) {
        if (!others_open) close_stroke();
        return;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const bool undo = r == SculptRequest::kUndo;
    ++(undo ? stats_.undo_requests : stats_.redo_requests);
    close_stroke(others_open ? std::optional<std::uint8_t>(site) : std::nullopt);  // journalled before the undo
    const std::uint64_t next = undo ? history_->next_undo_serial() : history_->next_redo_serial();
    if (const std::optional<std::uint8_t> by = undo ? sites_.blocks_undo(site, next) : sites_.blocks_redo(site, next)) {
        refuse(r, site, *by, next);
        return;
    }
    // The whole gesture: the parts other sites' cuts split it into go back (or come back) together.
    for (std::uint64_t at = next; at != 0 && sites_.same_gesture(at, next);
         at = undo ? history_->next_undo_serial() : history_->next_redo_serial())
        if (restore(undo, t0).serial == 0) break;
}

compute::UndoHistory::Change SculptThread::restore(bool undo, const std::chrono::steady_clock::time_point& t0) {
    const compute::UndoHistory::Change c = undo ? history_->undo() : history_->redo();
    if (c.serial == 0) return c;  // nothing to undo / redo
    if (undo) undo_clock_.undone(c.serial, stats_.samples);
    if (c.lattice) relattice_after(undo);  // a coarseness change taken back or made again: the whole model is new
    record_mark(undo ? compute::kJournalUndo : compute::kJournalRedo, c.serial, c.rays);
    changed_since_checkpoint_ = true;
    publish(published_centre_m_);  // the haptic window follows at once
    const auto t1 = std::chrono::steady_clock::now();
    const double contour_ms = contour_changed(t0, t1);
    stats_.undo_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    stats_.undo_rays.push_back(c.rays);
    stats_.undo_redo.push_back(undo ? 0 : 1);
    stats_.undo_restore_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    stats_.undo_contour_ms.push_back(contour_ms);
    return c;
}

void SculptThread::follow_host(SiteIntake& intake, std::uint8_t own_site, FollowerOutlet outlet,
                               std::optional<FollowStart> from) {
    if (thread_.joinable()) throw Error("SculptThread::follow_host: call it before start()");
    if (own_site == 0 || own_site >= kMaxSites)
        throw Error("SculptThread::follow_host: a joiner's site is 1.." + std::to_string(kMaxSites - 1) + ", not " +
                    std::to_string(own_site));
    if (!outlet.samples || !outlet.request) throw Error("SculptThread::follow_host: the outlet needs both functions");
    intake_ = &intake;
    local_site_ = own_site;
    outlet_ = std::move(outlet);
    follower_ = true;
    following_ = true;  // strokes close where the host's marks say, never for idling
    follow_start_ = std::move(from);
}

void SculptThread::use_snapshots(std::function<void(SculptSnapshot&&)> out) {
    if (thread_.joinable()) throw Error("SculptThread::use_snapshots: call it before start()");
    snapshot_out_ = std::move(out);
}

void SculptThread::use_snapshot_asks(std::function<void(SculptSnapshot&&)> out) {
    if (thread_.joinable()) throw Error("SculptThread::use_snapshot_asks: call it before start()");
    ask_out_ = std::move(out);
}

SculptSnapshot SculptThread::snapshot_now(std::uint8_t site) const {
    SculptSnapshot s;
    s.site = site;
    s.model = model_;
    // Where it goes it has never been contoured: every tile is to be (a .tdx keeps the flags).
    std::fill(s.model.tiles.dirty.begin(), s.model.tiles.dirty.end(), compute::TileGrid::kWhole);
    s.history = history_->save_steps();
    for (std::uint8_t k = 0; k < kMaxSites; ++k)
        if (const ToolSample* p = sites_.sweeps().prev(k)) s.prevs.push_back(*p);
    s.last_closed_serial = last_closed_serial_;
    return s;
}

void SculptThread::take_snapshot(std::uint8_t site) {
    if (!snapshot_out_) return;
    close_stroke(site);  // as another site's cut closes it: the open gesture goes on in its next stroke
    snapshot_out_(snapshot_now(site));
}

void SculptThread::serve_snapshot_asks() {
    const std::uint64_t asked = snapshot_asks_.load(std::memory_order_acquire);
    if (asked == snapshot_asks_served_ || history_->stroke_open()) return;
    snapshot_asks_served_ = asked;
    SculptSnapshot s = snapshot_now(0);
    s.asks = asked;
    ask_out_(std::move(s));
}

void SculptThread::forward_own(ToolSample s) {
    s.site = local_site_;
    ++stats_.forwarded;
    prev_ = s;  // the active surface follows this site's own tool at once, not its echo from the host
    have_prev_ = true;
    own_.push_back(s);
    if (!held_requests_.empty() && !tool_cuts(s)) take_held_requests();
}

void SculptThread::follow_check(std::uint64_t host_digest) {
    const std::uint64_t here = compute::model_digest(model_);
    ++stats_.digest_checks;
    if (here == host_digest) return;
    char text[160];
    std::snprintf(text, sizeof text, "this replica's model (digest %016llx) differs from the host's (%016llx)",
                  static_cast<unsigned long long>(here), static_cast<unsigned long long>(host_digest));
    if (outlet_.mismatch) outlet_.mismatch(text);
    throw Error(std::string("following the host: ") + text);
}

void SculptThread::follow_mark(const SiteEntry& e) {
    const auto t0 = std::chrono::steady_clock::now();
    if (e.mark == compute::kJournalStrokeEnd) {
        if (history_->stroke_open()) close_stroke();
        if (last_closed_serial_ != e.serial)
            throw Error("following the host: it closed stroke " + std::to_string(e.serial) + " where this replica closed " +
                        std::to_string(last_closed_serial_));
        return;
    }
    close_stroke();
    const bool undo = e.mark == compute::kJournalUndo;
    const compute::UndoHistory::Change c = restore(undo, t0);
    if (c.serial != e.serial || c.rays != e.rays)
        throw Error(std::string("following the host: its ") + (undo ? "undo" : "redo") + " of stroke " +
                    std::to_string(e.serial) + " (" + std::to_string(e.rays) + " rays) is stroke " +
                    std::to_string(c.serial) + " (" + std::to_string(c.rays) + " rays) here");
}

bool SculptThread::take_marks(StepWork& w) {
    if (next_mark_ >= follow_.size() || follow_[next_mark_].after_samples > stats_.samples) return false;
    flush(w.begin, w.n, w.changed);  // the sweeps before the mark go first, as they did live
    w.begin = w.n;
    while (next_mark_ < follow_.size() && follow_[next_mark_].after_samples <= stats_.samples)
        take(follow_[next_mark_++].request, local_site_);
    return true;
}

void SculptThread::close_stroke(std::optional<std::uint8_t> by_site) {
    const bool holding = holding_reference();
    const bool was_open = history_->stroke_open();
    const auto t0 = std::chrono::steady_clock::now();
    // The samples left unswept within the sweep spacing: the stroke ends where the tool did.
    bool tail_changed = false;
    if (sites_.sweeps().finish_strokes(compute::symmetry_centre(model_.lattice), batch_) > 0) flush(0, 0, tail_changed);
    compute::BooleanStats held;  // the stroke's last push group, held back until now (SculptHistory::apply)
    IslandRemoval islands;       // the specks the stroke left, removed
    const std::uint64_t serial = history_->end_stroke(&held, &islands);
    if (was_open) sites_.closed(serial, serial != 0 && history_->next_undo_serial() == serial, by_site);
    if (serial != 0) last_closed_serial_ = serial;
    if (held.rays_changed > 0) {
        undo_clock_.changed(stats_.samples);
        stats_.rays_changed += held.rays_changed;
        stroke_changed_ = true;
        changed_since_checkpoint_ = true;
        last_change_t_s_ = open_t_s();
    }
    // Timed by its newest change, the held push group's included.
    if (serial != 0 && history_->next_undo_serial() == serial) undo_clock_.closed(serial);
    stats_.islands += islands;
    if (islands.searches > 0) stats_.island_search_ms.push_back(islands.search_ms);
    if (islands.specks > 0) changed_since_checkpoint_ = true;
    const bool reference_moves = holding && stroke_changed_;
    stroke_changed_ = false;
    push_stroke_ = false;
    if (serial != 0) record_mark(compute::kJournalStrokeEnd, serial, 0);
    // Plastic: the deformed surface is the new reference (held sweeps are pushes, so their change lands here too).
    // Removed specks leave the haptic window too, and the tail the sweep spacing left reaches it as a step's cut does.
    if (reference_moves || islands.specks > 0 || (tail_changed && !holding)) publish(published_centre_m_);
    if (tail_changed || held.rays_changed > 0 || islands.specks > 0)
        contour_changed(t0, std::chrono::steady_clock::now(), was_open);
}

}  // namespace tridex::app
