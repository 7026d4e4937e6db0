// compute/runtime/sculpt_coarseness.cpp - the sculpt thread's coarseness changes: the model re-sampled onto a finer
// or coarser lattice as one undo step, and the contour and the tile cache made again for it (docs/commands/resample.md, "During a session").
#include <chrono>
#include <limits>

#include "compute/journal/journal_format.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/error.hpp"
#include "core/format.hpp"

namespace tridex::app {

void SculptThread::use_lattice_check(std::function<std::size_t(const compute::TriDexel&, int)> check) {
    if (thread_.joinable()) throw Error("SculptThread::use_lattice_check: call it before start()");
    lattice_check_ = std::move(check);
}

void SculptThread::coarse_first_on_lattice_change(bool on) {
    if (thread_.joinable()) throw Error("SculptThread::coarse_first_on_lattice_change: call it before start()");
    relattice_coarse_first_ = on;
}

std::string SculptThread::coarseness_refusal() const {
    if (gpu_contour_) return "the contour runs on the GPU, whose buffers hold this lattice (run with --cpu-contour)";
    if (!streams_.empty() || intake_ || follower_)
        return "this model is shared (a shared session or a cluster wall follows its stream), and the copies "
               "elsewhere cannot change their lattice yet";
    return "";
}

void SculptThread::coarseness_line(const std::string& line) {
    std::lock_guard<std::mutex> lock(save_mutex_);
    save_status_.coarseness = line;
}

void SculptThread::change_coarseness(SculptRequest r, std::uint8_t site) {
    const auto t0 = std::chrono::steady_clock::now();
    const int before = compute::lattice_resolution(model_.lattice);
    const int after = r == SculptRequest::kFiner ? before * 2 : before / 2;
    const std::string what = std::string(r == SculptRequest::kFiner ? "finer" : "coarser") + " (N = " +
                             std::to_string(before) + " -> " + std::to_string(after) + ")";
    std::string why = coarseness_refusal();
    if (why.empty() && (after < compute::kResampleMinResolution || after > compute::kResampleMaxResolution))
        why = "N = " + std::to_string(after) + " is outside " + std::to_string(compute::kResampleMinResolution) + ".." +
              std::to_string(compute::kResampleMaxResolution);
    if (!why.empty()) {
        coarseness_line("coarseness " + what + " refused: " + why);
        return;
    }
    close_stroke();  // journalled before the change
    CoarsenessChange done;
    try {
        const std::size_t max_bytes = lattice_check_ ? lattice_check_(model_, after) : std::numeric_limits<std::size_t>::max();
        done.serial = history_->resample(after, max_bytes, &done.resample).serial;
        done.resample_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    } catch (const Error& e) {
        coarseness_line("coarseness " + what + " refused: " + e.what());
        return;
    }
    if (site == local_site_) stats_.marks.push_back({stats_.samples, r});
    last_closed_serial_ = done.serial;
    undo_clock_.made(done.serial, stats_.samples);
    record_mark(compute::kJournalLattice, done.serial, static_cast<std::uint64_t>(after));
    changed_since_checkpoint_ = true;
    relattice();
    publish(published_centre_m_);
    contour_changed(t0, std::chrono::steady_clock::now());
    done.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const compute::ResampleStats& s = done.resample;
    const double dv = s.volume_before_m3 > 0.0 ? 100.0 * (s.volume_after_m3 / s.volume_before_m3 - 1.0) : 0.0;
    coarseness_line("coarseness: N = " + std::to_string(before) + " -> " + std::to_string(after) + ", cell " +
                    format_fixed(1e3 * s.cell_before_m, 3) + " -> " + format_fixed(1e3 * s.cell_after_m, 3) + " mm, volume " +
                    (dv >= 0.0 ? "+" : "") + format_fixed(dv, 2) + " %, " + format_fixed(done.seconds, 2) + " s (Ctrl+Z takes it back)");
    stats_.coarseness.push_back(done);
}

void SculptThread::relattice_after(bool undo) {
    relattice();
    const int n = compute::lattice_resolution(model_.lattice);
    coarseness_line(std::string("coarseness: ") + (undo ? "change undone" : "change redone") + ", N = " +
                    std::to_string(n) + ", cell " + format_fixed(1e3 * model_.lattice.cell_m, 3) + " mm");
}

void SculptThread::relattice() {
    contourer_ = compute::Contourer(model_);
    refiner_.reset();  // a start-up's refinement belonged to the old lattice
    shared_tiles_.clear();
    shared_groups_.clear();
    tile_cache_ = compute::TileSurfaceCache{};
    if (lod_options_) {
        // As at start-up: with coarse groups the new lattice is shown by its coarsest group levels first and its
        // tiles are contoured after them, nearest the tool first (every tile is dirty, none contoured yet).
        compute::LodWorkerOptions o = *lod_options_;
        o.coarse_first =
            relattice_coarse_first_ && compute::coarse_groups_apply(model_.lattice.cells, o.coarse_groups_from_cells);
        o.lod.cell_m = model_.lattice.cell_m;
        arm_tile_lod(o);
    }
    mesh_pending_ = mesh_out_ != nullptr;
}

}  // namespace tridex::app
