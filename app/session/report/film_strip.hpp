// app/session/report/film_strip.hpp - a session told in pictures: the model as its journal carves it, at moments spread over
// the stretch where it changed, rendered side by side into one PNG (for a README, a report, a bug).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "app/menu/menu_frame.hpp"
#include "app/scene/workpiece_source.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/journal/journal_replay.hpp"
#include "core/material_palette.hpp"
#include "core/progress.hpp"
#include "core/tool_shape.hpp"

namespace tridex::gpu {
class Context;
}

namespace tridex::app {

/// How to draw a film strip.
struct FilmStripOptions {
    int frames = 6;       ///< pictures, 2..24
    int width = 320;      ///< each picture's size, px (16..2048)
    int height = 240;
    bool ao = true;       ///< ambient occlusion (SceneView::occlusion_strength 1, else 0)
    int gap_px = 4;       ///< white columns between pictures, 0..64
    /// The recorded session's menu track: a picture at a device time when the menu was shown draws it as the session
    /// did (where it stood in the scene, its ring and lit slice). nullptr = no menu.
    const MenuTrack* menu = nullptr;
    /// Hears the fraction of the strip drawn (core/progress.hpp); empty = nobody.
    ProgressFn progress{};
    /// The materials' colours the pictures are drawn with (core/material_palette.hpp); nullptr = the default palette.
    const MaterialPalette* palette = nullptr;
};

/// Checks `opt` against the ranges above; throws tridex::Error "film strip: ..." naming the field out of range.
void check_film_strip_options(const FilmStripOptions& opt);

/// What write_film_strip drew.
struct FilmStrip {
    std::vector<std::size_t> records;  ///< per picture: records applied before it, of the journal split_batches made
    std::vector<double> t_s;           ///< per picture: device time of the last sample applied, s (0: none yet)
    std::vector<double> volume_m3;     ///< per picture: the model's volume, m^3
    std::vector<bool> menu_shown;      ///< per picture: the menu was drawn (FilmStripOptions::menu)
    int width = 0, height = 0;         ///< the whole strip's size, px
};

/// Draws the session of `journal` (its records as the sculpt thread journalled them) applied to `start` (the session's
/// workpiece before its first sample) as opt.frames pictures left to right, stopping where strip_picture_records says
/// (app/session/report/strip_moments.hpp: on the journal split by split_batches into pieces of kStripPieceSamples, after
/// record_changes), each showing the model then (applied in one pass; a clay push group still held at a picture shows
/// from the next one, and the last picture shows the final model; contoured on the CPU) and the tool at the last sample
/// applied (with its symmetric copies as ghosts while the sample carried a symmetry: app/session/view/symmetry_view.hpp),
/// framed as the demo frames its workpiece (framing_screen, one eye), and writes it to `path` as a PNG. `tool`
/// is the session's tool (radius for the ball drawn); `replay` the session's replay settings (replay_settings: speck
/// removal and clay group size; its undo budget is raised so that every undo finds its stroke). Throws tridex::Error
/// for options out of range, a journal the model refuses (as journal_apply), no Vulkan device, or a PNG that cannot be
/// written.
FilmStrip write_film_strip(const std::string& path, const compute::Journal& journal, const Workpiece& start,
                           const ToolShape& tool, const compute::JournalApplyFrom& replay, const FilmStripOptions& opt,
                           gpu::Context& context);

}  // namespace tridex::app
