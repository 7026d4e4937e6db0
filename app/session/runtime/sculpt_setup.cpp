// app/session/runtime/sculpt_setup.cpp - a session's sculpt thread set up: settings, checkpoints and saves.
#include "app/session/runtime/sculpt_setup.hpp"

#include <filesystem>

#include "compute/model/tdx_file.hpp"
#include "compute/tools/model_resample.hpp"

namespace tridex::app {

void set_session_sculpting(SculptThread& sculpt, const SessionSpec& spec, SessionKind kind) {
    sculpt.set_history_budget(spec.history_budget_bytes);
    sculpt.use_lattice_check([kind](const compute::TriDexel& m, int resolution) {
        return check_resample_memory(m, resolution, kind);
    });
    sculpt.remove_islands(!spec.keep_islands);
    // A stroke held on a button (the mouse's left button, a Flystick's trigger) must not split when the hand stops,
    // and an undo asked as the button is released takes back that whole stroke.
    if (driver_caps(spec.device_driver).strokes_end_on_release) sculpt.strokes_end_on_release(true);
}

void stop_sculpting(SculptThread& sculpt, compute::JournalIntake* intake, compute::JournalWriter* journal) {
    try {
        sculpt.stop();
    } catch (...) {
        if (intake) intake->stop();
        if (journal) journal->close();
        throw;
    }
    if (intake) intake->stop();  // writes nothing more: every sample it got is in a batch record now
    if (journal) journal->close();
}

void use_session_checkpoints(SculptThread& sculpt, const std::string& journal_path, double interval_s,
                             const Mat4& to_world, const SessionSpec& spec) {
    if (journal_path.empty() || !(interval_s > 0.0)) return;
    const std::filesystem::path jp(journal_path);
    const std::string name = jp.filename().string() + ".checkpoint.tdx";
    const std::string path = (jp.parent_path() / name).string();
    sculpt.use_checkpoints(
        [name, path, to_world, settings = spec_to_json(spec), palette = spec.palette](const compute::TriDexel& m) {
            // Atomic: a failure keeps the previous one. The settings name the lattice saved (coarseness changes).
            compute::save_tdx(path, m, to_world,
                              settings_at_resolution(settings, compute::lattice_resolution(m.lattice)), 3, palette);
            const auto [crc, bytes] = file_crc32(path);
            return CheckpointFile{name, bytes, crc};
        },
        interval_s);
}

void use_session_saver(SculptThread& sculpt, const std::string& path, const Mat4& to_world, const SessionSpec& spec) {
    if (path.empty()) return;
    sculpt.use_saver([path, to_world, settings = spec_to_json(spec), palette = spec.palette](const compute::TriDexel& m) {
        compute::save_tdx(path, m, to_world, settings_at_resolution(settings, compute::lattice_resolution(m.lattice)), 3,
                          palette);
        return "saved " + path;
    });
}

}  // namespace tridex::app
