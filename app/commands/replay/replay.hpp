// app/commands/replay/replay.hpp - `tridex replay FILE --out DIR`: sculpt a recorded session again.
#pragma once

#include <string>

#include "app/session/report/film_strip.hpp"
#include "app/session/batch/session.hpp"

namespace tridex::app {

/// Reads the recording (devices/recording.hpp), rebuilds the recorded session's workpiece and haptic
/// loop from the settings in its header, plays the recorded device samples back through a ReplayDevice
/// (one per tick: as fast as the sculpting goes, HapticLoopConfig::free_run; with `realtime`, at the recorded
/// rate, 1 / period_s) and writes the same outputs as the demo into out.out; both paces give the same model. The tool
/// sample stream, and so the sculpted model, equals the live session's. Throws tridex::Error naming the
/// file on a bad recording or settings. `sculpt`: where the Booleans and the contour run (--cpu,
/// --cpu-contour, --gpu-contour, as for the demo); every path gives the same model. `save`: where the final model is
/// written (.tdx, as `demo --save`; "" = not saved); refused up front when it names the recording, the workpiece or
/// one of --out's files. `keep_islands`: keep the specks cuts left even when the recorded session removed them
/// (--keep-islands); false = the recording's setting (SessionSpec::keep_islands), so the model is the live one.
/// `strip`: when its path is set, the replay also journals its samples (out.out/session.tdj) and draws a film strip of
/// them (write_film_strip) into that PNG: a carve told in pictures, written from a recording so it can be made again.
struct StripRequest {
    std::string path;              ///< the PNG; "" = no strip
    FilmStripOptions options;      ///< pictures, their size, ambient occlusion
};
void run_replay(const std::string& recording_path, const OutputOptions& out, const SculptOptions& sculpt = {},
                const std::string& save = "", const StripRequest& strip = {}, bool keep_islands = false,
                bool realtime = false);

}  // namespace tridex::app
