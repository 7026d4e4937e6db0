// app/commands/run/run_cli.cpp - `tridex run` options and entry point.
#include "app/commands/run/run_cli.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <new>

#include "app/commands/command.hpp"
#include "app/session/run/run_session.hpp"
#include "app/session/cluster/cluster_session.hpp"
#include "app/session/shared/shared_session.hpp"
#include "app/session/runtime/session_companion.hpp"
#include "app/support/device_lost.hpp"
#include "devices/registry/device_registry.hpp"
#include "core/error.hpp"
#include "core/symmetry.hpp"
#include "renderer/output/stereo_output.hpp"

namespace tridex::app {

std::string device_option_help() {
    std::string help = "Device replacing the scene's: a profile of the simulated hand or a driver of `tridex devices`: ";
    const std::vector<std::string> choices = devices::builtin_registry().choices();
    for (std::size_t i = 0; i < choices.size(); ++i) {
        const devices::DriverInfo* d = devices::builtin_registry().find(choices[i].substr(0, choices[i].find_first_of(":[")));
        help += (i == 0 ? "" : " | ") + choices[i] + (d ? " (" + d->summary + ")" : "");
    }
    return help + ". Keys and buttons of each: docs/devices/";
}

void add_run_options(CLI::App& run, RunOptions& o) {
    CLI::App* cmd = &run;
    cmd->add_option("scene", o.scene, "Scene file (JSON); default: assets/default_scene.json");
    cmd->add_option("--display", o.display, "window | fullscreen | offscreen")->capture_default_str();
    cmd->add_option("--device", o.device, device_option_help());
    cmd->add_option("--haptic-rendering", o.haptic_rendering,
                    "With --device net:HOST:PORT: distributed (this session computes the force) or local (the device "
                    "server runs the god-object loop next to the device on the active surface this session sends)");
    cmd->add_option("--stereo", o.stereo, "Stereo output: " + renderer::stereo_output_names() +
                                              " (default: the display config's)");
    cmd->add_option("--monitor", o.monitor, "Fullscreen monitor: index or part of its name (default: primary)");
    cmd->add_option("--frames", o.frames, "Stop after N stereo frames (0: no limit)")->capture_default_str();
    cmd->add_option("--out", o.out, "Output folder: report.json; offscreen also left/right/output.png")
        ->capture_default_str();
    cmd->add_option("--display-config", o.display_config, "Display config file (JSON) replacing the scene's display");
    cmd->add_option("--wand", o.wand, "Scene navigation wand: none | dtrack:PORT[:FLYSTICK] (ART DTrack Flystick: hold the trigger to carry the scene, joystick up/down scales, button 1 opens the menu, button 2 re-centres; default: the scene's)");
    cmd->add_option("--symmetry", o.symmetry,
                    std::string("Sculpting symmetry about the workpiece's centre, replacing the scene's: ") +
                        symmetry_forms() + " (mirror planes through the centre, or N copies about an axis)");
    cmd->add_option("--bindings", o.bindings, "Bindings file: the tool's and the wand's buttons and joystick to actions (docs/formats/bindings.md; default: the scene's \"bindings\", else each driver's defaults)");
    cmd->add_option("--head", o.head, "Head pose provider: fixed | scripted | tracker | dtrack:PORT[:BODY] (ART DTrack over UDP; default: the scene's)");
    cmd->add_flag("--swap-eyes", o.swap_eyes, "Exchange the eyes on the display");
    cmd->add_option("--seconds", o.seconds, "Stop after S seconds of wall time (0: no limit)")->capture_default_str();
    cmd->add_flag("--validate", o.validate, "Enable the Vulkan validation layer");
    auto* cpu = cmd->add_flag("--cpu", o.cpu, "Sculpt on the CPU pool whatever the Vulkan device (default: by the device's type: the CPU pool on a CPU implementation such as lavapipe, the GPU compute path on a GPU)");
    cmd->add_flag("--gpu", o.gpu, "Sculpt on the GPU compute path (Vulkan) whatever the device's type, lavapipe included")->excludes(cpu);
    cmd->add_flag("--cpu-contour", o.cpu_contour,
                  "Contour on the CPU (tile meshes) even when sculpting on the GPU (default: GPU contouring, "
                  "drawn with indirect draws, on a real GPU; CPU contouring on a CPU Vulkan such as lavapipe)");
    cmd->add_flag("--gpu-contour", o.gpu_contour,
                  "Contour on the GPU even on a CPU Vulkan implementation (lavapipe), where it is slower; it reads the "
                  "model on the GPU, so there it also sculpts on the GPU compute path")
        ->excludes(cpu);
    cmd->add_flag("--gpu-clay", o.gpu_clay,
                  "Push, smooth, pull and grab on the GPU clay kernel even on a CPU Vulkan implementation (lavapipe), where "
                  "the CPU reference is faster (same result bit for bit); there it also sculpts on the GPU compute path")
        ->excludes(cpu);
    cmd->add_flag("--pace,!--no-pace", o.pace, "Offscreen: pace frames at the display's refresh rate");
    cmd->add_flag("--early-frames,!--fixed-pace", o.early_frames,
                  "Offscreen and paced: start a frame early (half a period after the last at the soonest) when a "
                  "sculpted change is published, like a variable-refresh display; --fixed-pace starts frames on the "
                  "refresh grid only");
    cmd->add_flag("--items,!--no-items", o.items, "Draw the proxy, the force arrow and the overlay");
    cmd->add_flag("--overlay-stats", o.overlay_stats, "The overlay also counts the tiles drawn and skipped per eye");
    cmd->add_flag("--test-pattern", o.test_pattern,
                  "Show the wall's test pattern instead of the workpiece: the screen's edges and grid, one label per "
                  "eye, cubes in front of and behind the screen, the head's and tool's positions (docs/wall.md)");
    cmd->add_flag("--tiles,!--no-tiles", o.tiles, "Workpiece as per-tile meshes (else the whole mesh)");
    cmd->add_flag("--cull,!--no-cull", o.cull, "Draw only the tiles inside each eye's frustum");
    cmd->add_option("--lod", o.lod,
                    "on | off | coarse | simplified (default on): tile levels of detail (built per re-contoured tile on a "
                    "worker thread, tiles drawn at full resolution until theirs arrive; each eye draws the coarsest level "
                    "whose error projects to at most a pixel); groups of tiles contoured from every 2nd, 4th, 8th ray of "
                    "the model (coarse; a tile's coarser level is then its group's) or simplified from their tiles "
                    "(simplified); on: coarse from 512 cells")
        ->capture_default_str();
    cmd->add_option("--startup", o.startup,
                    "coarse | full (default coarse): with coarse group levels (--lod on from 512 cells, or coarse), the "
                    "first frame draws the coarsest levels and the tiles replace them region by region as they are "
                    "contoured (coarse), or every tile is contoured before the first frame (full)")
        ->check(CLI::IsMember({"coarse", "full"}))
        ->capture_default_str();
    cmd->add_option("--stroke-contour", o.stroke_contour,
                    "coarse | full (default coarse): with coarse group levels, while a stroke is open its tiles wait "
                    "and the coarse levels over them draw it, and the tiles are contoured once it closes or where a "
                    "frame asks for more detail (coarse), or every step contours its tiles at full resolution (full)")
        ->check(CLI::IsMember({"coarse", "full"}))
        ->capture_default_str();
    cmd->add_option("--ao", o.ao,
                    "on | off: ambient occlusion (cuts shaded darker, edges brighter; default: the display config's "
                    "ambient_occlusion, on); key O toggles it in a window")
        ->check(CLI::IsMember({"on", "off"}));
    cmd->add_option("--ao-while-sculpting", o.ao_sculpting,
                    "on | off | auto: the ambient occlusion on frames drawn while sculpting (default auto: off on a "
                    "CPU implementation of Vulkan such as lavapipe, where it delays the carved surface; on otherwise)")
        ->check(CLI::IsMember({"on", "off", "auto"}));
    cmd->add_option("--frame-target-ms", o.frame_target_ms,
                    "Frame-time target the picture is budgeted to, ms: while the median frame is over it, the "
                    "occlusion is evaluated per 4x4 pixels instead of 2x2, then coarser levels of detail are drawn, "
                    "then a desk window's eyes are rendered smaller and scaled up (0 = no budget)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1000.0));
    cmd->add_option("--min-render-scale", o.min_render_scale,
                    "Lowest render scale the frame-time budget may choose in a desk window: eye images at this share "
                    "of the window's width and height, scaled up (0.5..1; 1 = always the window's size)")
        ->capture_default_str()
        ->check(CLI::Range(0.5, 1.0));
    cmd->add_option("--max-lod-px", o.max_lod_px,
                    "Coarsest levels of detail the frame-time budget may draw in a desk window, as their largest error "
                    "on screen, pixels (1..8; levels are drawn within 1 pixel until the budget needs more; 1 = never "
                    "coarser)")
        ->capture_default_str()
        ->check(CLI::Range(1.0, 8.0));
    cmd->add_option("--record", o.record, "Record the session to FILE (TRDXREC; `tridex replay FILE` sculpts it again)");
    cmd->add_option(
        "--falcon-firmware", o.falcon_firmware,
        "Novint Falcon firmware FILE from your own installation (the falcon driver loads it; never shipped)");
    cmd->add_option("--key-file", o.key_file,
                    "With --device net:HOST:PORT: the key FILE the device server seals its link with (--key-file there)");
    cmd->add_option("--passphrase-env", o.passphrase_env,
                    "With --device net:HOST:PORT: the environment variable VAR holding the passphrase the device server "
                    "seals its link with (its name, never the passphrase)");
    auto* workpiece = cmd->add_option("--workpiece", o.workpiece,
                                      "Start from a saved model FILE.tdx (--save, Ctrl+S) instead of the scene's workpiece");
    cmd->add_option("--mesh", o.mesh,
                    "Carve this closed mesh (OFF, OBJ, PLY, STL) instead of the scene's workpiece mesh, placed and sized as "
                    "the scene places its workpiece")
        ->excludes(workpiece);
    cmd->add_option("--save", o.save, "Save the final model to FILE.tdx (a later session or `tridex export` starts from it)");
    auto* journal = cmd->add_option("--journal", o.journal,
                                    "Session journal FILE (default: OUT/session.tdj; `tridex recover FILE` rebuilds the model)");
    cmd->add_flag("--no-journal", o.no_journal, "Write no session journal")->excludes(journal);
    cmd->add_option("--checkpoint-s", o.checkpoint_s,
                    "Seconds between checkpoint models written next to the journal while sculpting (0 = none)")
        ->capture_default_str();
    cmd->add_option("--history-mib", o.history_mib, "Memory for undo, MiB (default 256; oldest strokes dropped first)");
    cmd->add_flag("--keep-islands", o.keep_islands, kKeepIslandsHelp);
    cmd->add_flag("--shared-haptic-cpu", o.shared_haptic_cpu,
                  "Let the haptic loop share its CPU with the drawing thread (default: once the loop runs at "
                  "real-time priority, one CPU is set aside for it)");
    cmd->add_option("--cluster", o.cluster,
                    "Cluster config (JSON): run under mpirun (or with --cluster-listen / --cluster-connect), rank 0 "
                    "runs the session and the other ranks draw the wall's viewports (docs/cluster.md)");
    cmd->add_option("--cluster-listen", o.cluster_listen,
                    "A wall without mpirun: be its rank 0, listening on [ADDR:]PORT for the render ranks, which may "
                    "join while it runs or replace one that failed (docs/cluster.md)");
    cmd->add_option("--cluster-connect", o.cluster_connect,
                    "A wall without mpirun: draw render rank --rank's viewports for the rank 0 at HOST:PORT");
    cmd->add_option("--rank", o.cluster_rank, "With --cluster-connect: which render rank of the config this is (1..K)");
    cmd->add_option("--host", o.host,
                    "Host a shared session on [ADDR:]PORT: others join with --join and carve this model with you "
                    "(docs/shared.md)");
    cmd->add_option("--join", o.join, "Join the shared session hosted at HOST:PORT (its model is the workpiece)");
    cmd->add_option("--shared-key-file", o.shared_key_file,
                    "The shared session's key: a file of 32 bytes or 64 hex digits, the same at every site");
    cmd->add_option("--shared-passphrase-env", o.shared_passphrase_env,
                    "The shared session's key from a passphrase held in this environment variable");
    cmd->add_option("--name", o.site_name, "Your name in a shared session, as the others see it");
}

namespace {

// The run's summary on stdout.
void print_run(const RunResult& r) {
    std::printf("tridex run: %s %s, %llu frames (%llu presents) in %.2f s, frame p50 %.2f ms, GPU p50 %.2f ms\n",
                to_string(r.setup.display), std::string(renderer::to_string(r.setup.scene.display.stereo)).c_str(),
                static_cast<unsigned long long>(r.frames), static_cast<unsigned long long>(r.presents), r.render_s,
                r.frame_ms.percentile_ms(0.5), r.gpu_ms.percentile_ms(0.5));
    std::printf("  haptics %zu ticks (%zu overruns), sculpt %llu steps, %llu meshes drawn; volume %.6g -> %.6g m^3 "
                "(%.4g cm^3 %s)\n",
                r.loop.ticks, r.loop.overruns, static_cast<unsigned long long>(r.sculpt.steps),
                static_cast<unsigned long long>(r.mesh_versions_drawn), r.volume_before_m3, r.volume_after_m3,
                std::fabs(r.volume_before_m3 - r.volume_after_m3) * 1e6,
                r.volume_after_m3 > r.volume_before_m3 ? "added" : "removed");
    if (r.more_workpieces.is_array())  // a scene of several workpieces: each further one's own
        for (const nlohmann::json& m : r.more_workpieces) {
            const double before = m["volume_before_m3"].get<double>(), after = m["volume_after_m3"].get<double>();
            std::printf("  workpiece %d: sculpt %llu steps; volume %.6g -> %.6g m^3 (%.4g cm^3 %s)\n",
                        m["index"].get<int>() + 1, static_cast<unsigned long long>(m["sculpt"]["steps"].get<std::uint64_t>()),
                        before, after, std::fabs(before - after) * 1e6, after > before ? "added" : "removed");
        }
    if (r.sculpt.history.undos + r.sculpt.history.redos > 0 || r.saves.saves + r.saves.failures > 0)
        std::printf("  undo %llu, redo %llu (%zu strokes undoable), Ctrl+S saves %llu\n",
                    static_cast<unsigned long long>(r.sculpt.history.undos),
                    static_cast<unsigned long long>(r.sculpt.history.redos), r.sculpt.history.undo_steps,
                    static_cast<unsigned long long>(r.saves.saves));
    if (r.sculpt.islands.specks > 0)
        std::printf("  specks removed: %llu (%.3g mm^3 cut loose by strokes; --keep-islands keeps them)\n",
                    static_cast<unsigned long long>(r.sculpt.islands.specks), r.sculpt.islands.volume_m3 * 1e9);
    if (const auto it = r.companions.find("cluster"); it != r.companions.end() && it->is_object()) {
        const nlohmann::json& c = *it;
        std::printf("  cluster: %d ranks, %llu frames in step, %llu digest checks agreed, %.0f bytes per frame (mean), "
                    "swap spread p99 %.2f ms\n",
                    c.value("ranks", 0), static_cast<unsigned long long>(c.value("frames", 0ull)),
                    static_cast<unsigned long long>(c.value("checks", 0ull)), c.value("frame_bytes_mean", 0.0),
                    c["swap_spread_ms"].is_object() ? c["swap_spread_ms"].value("p99", 0.0) : 0.0);
        if (const auto e = c.find("events"); e != c.end() && e->is_array() && !e->empty()) {
            int joined = 0, let_go = 0;
            for (const nlohmann::json& x : *e) (x.value("what", "") == "joined" ? joined : let_go) += 1;
            std::printf("  cluster: %d render rank(s) let go, %d joined the running wall (report.json cluster.events)\n",
                        let_go, joined);
        }
    }
    for (const std::string& n : r.notes) std::printf("  %s\n", n.c_str());
    std::string written;
    for (const std::string& f : r.files) written += (written.empty() ? "" : ", ") + f;
    std::printf("  wrote: %s\n", written.empty() ? r.setup.out.c_str() : written.c_str());
}

}  // namespace

int run_command(const RunOptions& options) {
    const bool cluster = !options.cluster.empty();
    // A cluster's rank 0 that fails ends every rank once its own work is written (end_cluster_session).
    const auto failed = [cluster](int code) {
        if (cluster) end_cluster_session(code);
        return code;
    };
    try {
        if (cluster) {
            // A wall that hosts or joins a shared session: rank 0 is the site, its render ranks draw its replica.
            const ClusterRunResult c =
                run_cluster_session(options, shared_session_asked(options) ? RankZeroRun(run_shared_session) : RankZeroRun{});
            if (c.run) print_run(*c.run);
            return c.exit_code;
        }
        print_run(shared_session_asked(options) ? run_shared_session(options) : run_stereo_session(options));
        return 0;
    } catch (const DeviceLostError& e) {
        std::fprintf(stderr, "tridex: %s\n", e.what());
        return failed(4);
    } catch (const CompanionError& e) {  // a cluster's render rank failed: rank 0 kept its work, every rank ends
        std::fprintf(stderr, "tridex: %s\n", e.what());
        return failed(5);
    } catch (const Error& e) {
        std::fprintf(stderr, "tridex: %s\n", e.what());
        return failed(2);
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "tridex: out of memory; lower workpiece.resolution\n");
        return failed(3);
    }
}

}  // namespace tridex::app
