// app/session/record/session_recording.hpp - turning a session's haptic tick records into a recording file
// (Singapogu's Table 3 fields, devices/recording.hpp) and back into a replayable session.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "app/scene/session_spec.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "devices/recording.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app {

/// One recorded tick from a loop record: the raw device sample (the replay input), the tool pose as
/// axis-angle, the top and bottom points (points 0 and 1; with tool_points == 1 the point is recorded as
/// the top and a copy with no contact as the bottom), their collision points, deviations, forces and
/// collision ids, the summed force and torque, buttons, the op, material and tool the tick used (r.op,
/// r.material, r.tool; on a tick without them, an invalid sample: `op` and no tool) and the tool mode (that op,
/// kNone while modelling was paused). t_s is the device time when it advances past prev_t_s, else just after
/// prev_t_s.
devices::RecordedTick to_recorded_tick(const haptics::TickRecord& r, ToolOp op, double prev_t_s, int tool_points);

/// What is wrong with a tool a recording or journal says the session used ("" when nothing). Only the mouse
/// stylus's [ ] keys change a session's tool, by at most MouseStylus::kSizeStep^MouseStylus::kMaxSizeSteps either way
/// from the session's tool `session_tool`, so a tool of that kind whose radius (a flat end: or length) lies outside
/// that range (beyond a relative 1e-9) was not written by a session. A tool of another kind or of radius 0 (a
/// sample without a tool) is not checked.
std::string recorded_tool_problem(const ToolShape& session_tool, const ToolShape& used);

/// The op, material, symmetry, tool and workpiece changes of a recorded session, for its replay
/// (HapticLoopConfig::tool_schedule): one ToolChange at the device time of each valid tick whose op, material,
/// symmetry, tool or workpiece differs from the valid tick before it (the first from `spec`'s op, material, symmetry
/// and tool; the first tick that names its workpiece, from version 4 files, always sets it). Ticks without a recorded tool (version 1 files,
/// invalid ticks) change nothing; a recorded tool of another kind than spec.tool is ignored. Throws tridex::Error
/// "tick K: <what>" for a tool no session of `spec` uses (recorded_tool_problem).
std::vector<haptics::ToolChange> tool_schedule(const devices::Recording& rec, const SessionSpec& spec);

/// The sculpt thread's marks (SculptStats::marks: undos, redos, stroke closes) as a recording header keeps them, and,
/// merged among them by after_samples (each workpiece's after the first's at the same count), those of a session's
/// further workpieces (`more`[k-1] of workpiece k).
std::vector<devices::RecordedMark> recorded_marks(std::span<const SculptMark> marks,
                                                  std::span<const std::vector<SculptMark>> more = {});

/// The marks a replay follows on workpiece `workpiece` (SculptThread::follow_marks), from a recording's header;
/// nullopt when the file has none recorded (written before marks were kept). The header's marks were checked when it
/// was read.
std::optional<std::vector<SculptMark>> sculpt_marks(const devices::RecordingHeader& header, std::uint8_t workpiece = 0);

/// The records of a session without a sculpt thread (a simulated participant) as a recording in memory
/// (to_recorded_tick per record, the settings in the header notes, no marks), as write_session_recording writes it.
devices::Recording session_recording(const SessionSpec& settings, const std::vector<haptics::TickRecord>& records);

/// The header of a recording of a session of `settings`: its device profile's name, period and workspace mode,
/// `notes` ("" = spec_to_json(settings)) and the sculpt threads' `marks` and `more_marks` (recorded_marks).
/// `poses`: the haptic loop's pose sets (HapticLoop::pose_changes: placements undone and redone), kept in order.
devices::RecordingHeader recording_header(const SessionSpec& settings, const std::string& notes,
                                          std::span<const SculptMark> marks,
                                          std::span<const std::vector<SculptMark>> more_marks = {},
                                          std::span<const haptics::PoseChange> poses = {});

/// The pose sets a replay's loop repeats (HapticLoopConfig::pose_schedule) from a recording's header. Throws
/// tridex::Error "poses[k].workpiece = K, but the session has N workpieces" for a workpiece the session lacks.
std::vector<haptics::PoseChange> pose_schedule(const devices::RecordingHeader& header, std::size_t workpieces);

/// Writes the session's records to `path` (TRDXREC format) with `notes` in the header notes ("" = the settings,
/// spec_to_json) and the sculpt thread's `marks` (SculptStats::marks), so that a replay repeats its undos, redos
/// and strokes. Throws tridex::Error "<path>: ..." when it cannot write.
void write_session_recording(const std::string& path, const SessionSpec& settings,
                             const std::vector<haptics::TickRecord>& records, const std::string& notes = "",
                             std::span<const SculptMark> marks = {}, std::span<const haptics::PoseChange> poses = {});

}  // namespace tridex::app
