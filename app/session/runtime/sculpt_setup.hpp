// app/session/runtime/sculpt_setup.hpp - how a session sets up each of its sculpt threads: the spec's sculpting
// settings, and what the thread writes of its model beside the journal (the periodic checkpoint and the model saved on
// request, each with the session's settings and palette).
#pragma once

#include <string>

#include "app/scene/session_memory.hpp"
#include "app/scene/session_spec.hpp"
#include "compute/journal/journal_intake.hpp"
#include "compute/journal/journal_writer.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/math.hpp"

namespace tridex::app {

/// Sets `sculpt` up as `spec` asks: its undo history budget, speck removal (keep_islands), no idle stroke closes for a
/// driver whose strokes end when a button is released, and a coarseness change refused, with the memory it would
/// take, when the finer model and its contour do not fit a session of `kind` (check_resample_memory). Throws
/// tridex::Error when the thread runs.
void set_session_sculpting(SculptThread& sculpt, const SessionSpec& spec, SessionKind kind);

/// Stops `sculpt` (SculptThread::stop: drains its ring, closes the stroke, syncs the journal), then `intake` and
/// `journal` (either may be null), these also when the thread failed, whose failure is then rethrown.
void stop_sculpting(SculptThread& sculpt, compute::JournalIntake* intake, compute::JournalWriter* journal);

/// Makes `sculpt` write a checkpoint model "<journal file name>.checkpoint.tdx" beside `journal_path` every
/// `interval_s` (s; SculptThread::use_checkpoints) with spec_to_json(spec) as its settings (at the lattice then
/// saved), `to_world` and spec.palette, atomically; interval_s <= 0 or an empty journal path: none. Throws
/// tridex::Error when the thread runs.
void use_session_checkpoints(SculptThread& sculpt, const std::string& journal_path, double interval_s,
                             const Mat4& to_world, const SessionSpec& spec);

/// Makes `sculpt` save its model to `path` (.tdx, atomically) on each SculptRequest::kSave, with spec_to_json(spec)
/// as its settings (at the lattice then saved), `to_world` and spec.palette; "" = no saver. Throws tridex::Error
/// when the thread runs.
void use_session_saver(SculptThread& sculpt, const std::string& path, const Mat4& to_world, const SessionSpec& spec);

}  // namespace tridex::app
