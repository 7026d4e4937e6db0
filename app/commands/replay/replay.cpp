// app/commands/replay/replay.cpp - replaying a recorded session.
#include "app/commands/replay/replay.hpp"

#include <algorithm>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <vector>
#include <optional>

#include "app/support/output_dir.hpp"
#include "app/session/record/session_recording.hpp"
#include "app/support/progress.hpp"
#include "app/scene/session_spec.hpp"
#include "app/scene/workpiece_list.hpp"
#include "app/scene/workpiece_source.hpp"
#include "compute/journal/journal_reader.hpp"
#include "core/error.hpp"
#include "gpu/context.hpp"
#include "devices/recording.hpp"
#include "devices/registry/device_registry.hpp"
#include "devices/mouse_device.hpp"
#include "devices/replay_device.hpp"

namespace tridex::app {

void run_replay(const std::string& recording_path, const OutputOptions& out, const SculptOptions& sculpt,
                const std::string& save, const StripRequest& strip, bool keep_islands, bool realtime) {
    const auto t_start = std::chrono::steady_clock::now();
    check_image_size(out.width, out.height);
    prepare_output_dir(out.out, "--out");
    if (!save.empty()) check_output_file(save, "--save");
    const std::string strip_journal = (std::filesystem::path(out.out) / "session.tdj").string();
    if (!strip.path.empty()) {
        try {
            check_film_strip_options(strip.options);
        } catch (const Error& e) {
            throw Error(std::string("--strip-frames/--strip-size: ") + e.what());
        }
        check_output_file(strip.path, "--strip");
        check_distinct_files({{"--strip", strip.path}, {"--out's session.tdj", strip_journal}},
                             {{"the recording", recording_path}});
    }
    const devices::Recording rec = devices::read_recording(recording_path);
    SessionSpec s = spec_from_json(rec.header.notes, recording_path);
    if (keep_islands) s.keep_islands = true;
    if (!save.empty()) {
        std::vector<NamedFile> outputs{{"--save", save}};
        for (const char* name : kSessionOutputFiles)
            outputs.push_back({std::string("--out's ") + name, (std::filesystem::path(out.out) / name).string()});
        check_distinct_files(outputs, {{"the recording", recording_path}, {"the workpiece", s.model_path.empty() ? s.mesh_path : s.model_path}});
    }
    // Changed files first: validating the spec loads the tool mesh, and would fail less clearly.
    check_inputs_unchanged(s, recording_path, "the recording");
    validate_spec(s, recording_path);
    Workpiece wp = prepare_session_workpiece(s);
    std::vector<Workpiece> more = prepare_more_workpieces(s);  // a session's further workpieces
    // The menu as the recorded session showed it, for the film strip's pictures.
    const MenuTrack menu_track = MenuTrack::from_json_text(rec.header.menu, recording_path);
    std::optional<Workpiece> strip_start;  // the film strip replays the journal from the workpiece as it was
    if (!strip.path.empty()) strip_start = wp;
    // The keys' op and tool changes at their ticks, and the mouse's engage button, so the replayed samples carry
    // what the recorded ones carried.
    LoopOverrides loop;
    try {
        loop.tool_schedule = tool_schedule(rec, s);
        loop.pose_schedule = pose_schedule(rec.header, 1 + more.size());
    } catch (const Error& e) {
        throw Error(recording_path + ": " + e.what());
    }
    loop.engage_mask = engage_mask_for(s.device_driver);
    loop.free_run = !realtime;  // nothing is drawn while it runs: nothing to keep pace with
    loop.recorded_ticks = rec.ticks.size();
    // The recorded samples played back through the registry's replay driver, with the recorded profile.
    s.device_driver = "replay";
    devices::DeviceInputs inputs;
    inputs.period_s = s.period_s;
    inputs.samples = devices::device_states(rec);
    std::unique_ptr<devices::HapticDevice> device = make_device(s, inputs);
    const Vec3 start = rec.ticks.empty() ? s.device_origin_m : rec.ticks.front().wand_centre_m;
    // Until the replay device runs out of samples (it then "vanishes"); wall time is a safety net.
    const double timeout_s = 3.0 * static_cast<double>(rec.ticks.size()) * s.period_s + 10.0;
    SculptOptions so{sculpt.cpu, out.validate, sculpt.cpu_contour, sculpt.gpu_contour, strip.path.empty() ? "" : strip_journal};
    so.gpu_clay = sculpt.gpu_clay;
    so.gpu = sculpt.gpu;
    // The live session's undos, redos and stroke closes where its sculpt thread took them.
    so.follow_marks = sculpt_marks(rec.header);
    for (std::size_t k = 1; k <= more.size(); ++k)  // each further workpiece's own
        loop.more_follow_marks.push_back(sculpt_marks(rec.header, static_cast<std::uint8_t>(k)).value_or(std::vector<SculptMark>{}));
    std::optional<SessionRun> run;
    try {
        run.emplace(run_session(s, std::move(wp), std::move(device), 0, rec.ticks.size() + 1000, timeout_s, start, so,
                                loop, std::move(more)));
    } catch (const Error& e) {  // what the recorded samples asked for (a sweep too far away, ...): name the file
        throw Error(recording_path + ": " + e.what());
    }
    OutputOptions named = out;
    named.command = "replay";
    OutputWrites writes;
    write_session_outputs(named, *run, t_start, writes);
    if (!save.empty()) {
        writes.attempt(save, [&] { save_session_model(save, run->runtime->workpiece(), run->runtime->spec()); });
        for (std::size_t k = 1; k < run->runtime->workpiece_count(); ++k) {  // each further workpiece beside it
            const std::string path = path_for_workpiece(save, k);
            const MoreWorkpiece& m = run->runtime->more_workpiece(k);
            writes.attempt(path, [&] { save_session_model(path, m.workpiece(), m.spec()); });
        }
    }
    if (strip_start) {
        writes.attempt(strip.path, [&] {
            const compute::Journal j = compute::read_journal(strip_journal);
            gpu::ContextOptions gopt;
            gopt.validation = out.validate;
            gpu::Context ctx = gpu::Context::create(gopt);
            FilmStripOptions so = strip.options;
            if (menu_track.size() > 0) so.menu = &menu_track;
            ProgressReporter::Step step = progress().step("drawing the film strip");
            so.progress = step.fn();
            so.palette = &s.palette;
            const FilmStrip f = write_film_strip(strip.path, j, *strip_start, s.tool, replay_settings(s), so, ctx);
            step.finish();
            const auto with_menu = std::count(f.menu_shown.begin(), f.menu_shown.end(), true);
            std::printf(
                "film strip: %d pictures (%d with the menu) from %.2f s to %.2f s of device time, %dx%d px, %s\n",
                strip.options.frames, static_cast<int>(with_menu), f.t_s.front(), f.t_s.back(), f.width, f.height,
                strip.path.c_str());
            if (ctx.validation_messages() > 0)
                throw Error("the Vulkan validation layer reported " + std::to_string(ctx.validation_messages()) +
                            " message(s) while drawing the film strip");
        });
    }
    writes.finish(out.out);
}

}  // namespace tridex::app
