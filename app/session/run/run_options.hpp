// app/session/run/run_options.hpp - the command-line options of `tridex run` (SI units; strings checked when the run starts).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace tridex::app {

class SessionRuntime;

/// What a monitor of a run (RunOptions::frame_probe) is told after every frame, on the frame thread.
struct RunFrameProbe {
    std::uint64_t frame = 0;  ///< the frame's number (0 first)
    double frame_ms = 0.0;    ///< its CPU wall time, draw + readback or present, ms (as RunResult::frame_ms)
    std::size_t triangles = 0;  ///< triangles of the workpiece's mesh it drew (as RunResult::triangles)
    /// The session's threads, for counters any thread may read (SessionRuntime::loop_stats, sculpt_live).
    const SessionRuntime* runtime = nullptr;
};

/// Where a run shows its frames.
enum class DisplayKind {
    kWindow,      ///< [window] a GLFW window, vsync'd presentation
    kFullscreen,  ///< [fullscreen] fullscreen on a chosen monitor, vsync'd presentation
    kOffscreen,   ///< [offscreen] no window: the same passes, images and report written to --out
};

/// "window", "fullscreen" or "offscreen".
const char* to_string(DisplayKind kind);
/// Inverse of to_string; throws tridex::Error "--display: 'x' is not one of window, fullscreen, offscreen".
DisplayKind parse_display_kind(const std::string& name);

/// Options of `tridex run [SCENE]`. Empty strings and zero limits mean "as the scene says" / "no limit".
struct RunOptions {
    std::string scene;              ///< scene file (JSON, app/scene/run_scene.hpp); empty = assets/default_scene.json
    std::string display = "window"; ///< window | fullscreen | offscreen
    /// Device driver replacing the scene's (simulated, mouse, spacemouse, or net:HOST:PORT for a device served by
    /// `tridex device-server`); empty = the scene's.
    std::string device;
    /// With a net device: distributed (this session renders the force) or local (the server renders contact next
    /// to the device); empty = the scene's device.haptic_rendering (distributed).
    std::string haptic_rendering;
    std::string stereo;             ///< stereo output name (renderer parse_stereo_output); empty = the display config's
    std::string monitor;            ///< fullscreen monitor: an index (digits) or part of its name; empty = primary
    int frames = 0;                 ///< stop after this many stereo frames (>= 0; 0 = no frame limit)
    std::string out = "out/run";    ///< output folder (created): report.json, and offscreen left/right/output.png
    std::string display_config;     ///< display config file replacing the scene's display; empty = the scene's
    std::string wand;               ///< scene navigation wand: none | dtrack:PORT[:FLYSTICK]; empty = the scene's
    std::string bindings;           ///< bindings file (docs/formats/bindings.md); empty = the scene's, else the drivers'
    /// Sculpting symmetry replacing the scene's (core/symmetry.hpp spelling: off, x, xz, radial:6:z, ...); empty = the
    /// scene's.
    std::string symmetry;
    std::string head;               ///< head provider fixed | scripted | tracker | dtrack[:PORT[:BODY]]; empty = the scene's
    bool swap_eyes = false;         ///< exchange the eyes (in addition to the display config's swap_eyes)
    double seconds = 0.0;           ///< stop after this much wall time, s (>= 0; 0 = no time limit)
    bool validate = false;          ///< Vulkan validation layer (also on with TRIDEX_VALIDATION=1)
    /// Sculpt on the CPU pool whatever the Vulkan device; with neither this nor `gpu` the device's type decides
    /// (compute/runtime/backend_choice.hpp decide_backend).
    bool cpu = false;
    bool gpu = false;               ///< sculpt on the GPU compute path whatever the device's type (--gpu)
    /// Contour dirty tiles on the CPU (per-tile meshes uploaded to the renderer) even when the Booleans run
    /// on the GPU; by default a GPU sculpt path also contours on the GPU and the renderer draws its buffers
    /// with indirect draws.
    bool cpu_contour = false;
    /// Contour on the GPU even on a CPU implementation of Vulkan (lavapipe), where CPU contouring is the
    /// default because it is faster there (app/session/batch/session.hpp gpu_contour_default).
    bool gpu_contour = false;
    /// --gpu-clay: clay sweeps on the GPU clay kernel even on a CPU Vulkan implementation (lavapipe).
    bool gpu_clay = false;
    /// Offscreen: pace frames at the display's refresh rate as a vsync'd display would (false: as fast as the
    /// GPU renders; for benchmarks).
    bool pace = true;
    /// Offscreen and paced: a frame starts early, half a period after the last at the soonest, when the sculpt
    /// thread publishes a sculpted change, like a display with a variable refresh rate (false: frames start only on
    /// the refresh rate's grid, as on a fixed-rate display).
    bool early_frames = true;
    /// Draw the proxy, the force arrow and the overlay (haptic rate, sculpt rate, frame time, tiles drawn /
    /// skipped); false: the workpiece, tool, workspace box and bubble only.
    bool items = true;
    /// The overlay also counts the tiles drawn and skipped per eye (a developer's figure; off: a person's overlay).
    bool overlay_stats = false;
    /// Show the wall's test pattern (app/scene/test_pattern.hpp) instead of the workpiece, and the head's and the
    /// tool's positions in the overlay: for checking a display config's corners, the eye order and the tracker's
    /// origin (docs/wall.md).
    bool test_pattern = false;
    /// The workpiece as per-tile meshes (only changed tiles re-uploaded, tiles culled per eye); false: the
    /// whole mesh every publish (the fallback path).
    bool tiles = true;
    /// With tiles: draw only the tiles inside each eye's off-axis frustum (false: every tile in both eyes).
    bool cull = true;
    /// With tiles: "on" builds each changed tile's levels of detail on a worker thread (never waited for) and
    /// draws each tile per eye at the coarsest level whose error projects to at most a pixel; "off": full meshes.
    std::string lod = "on";
    /// "coarse": with coarse group levels, the first mesh holds the coarsest levels and the tiles are contoured after
    /// it, region by region; "full": every tile is contoured before the first mesh (docs/design/lod.md).
    std::string startup = "coarse";
    /// --stroke-contour: coarse | full (SculptOptions::stroke_coarse).
    std::string stroke_contour = "coarse";
    /// "on" | "off": screen-space ambient occlusion (cuts darker, edges brighter); "" = the display config's
    /// ambient_occlusion (on unless it says false). Key O toggles it in a window.
    std::string ao;
    /// "on" | "off" | "auto": the ambient occlusion on frames drawn while the workpiece is being sculpted (within
    /// 0.3 s of a sculpted change). "auto": off on a CPU implementation of Vulkan (lavapipe), where its passes
    /// lengthen every frame between the tool and the drawn surface, on otherwise. The session's last frame always
    /// has it when the occlusion is on.
    std::string ao_sculpting = "auto";
    /// The frame-time target, ms, that the picture is budgeted to (app/session/view/frame_budget.hpp): while the median
    /// frame is over it the occlusion is evaluated per 4x4 pixels instead of per 2x2, then the levels of detail may
    /// stray up to max_lod_px pixels, then a desk window's eye images are rendered smaller (down to min_render_scale)
    /// and scaled up. 0 = no budget. Finite and >= 0.
    double frame_target_ms = 25.0;
    /// The lowest render scale (eye image size / window size, per axis) the budget may choose in a desk window,
    /// 0.5..1; 1 = always the window's size. Fullscreen and offscreen sessions always render at their size.
    double min_render_scale = 0.75;
    /// The coarsest levels of detail the budget may draw in a desk window, as their largest error on screen, pixels,
    /// 1..8 (the finest step draws levels within 1 pixel; 1 = never coarser). Only with --lod on; fullscreen and
    /// offscreen sessions always draw levels within 1 pixel.
    double max_lod_px = 2.0;
    /// When set, the session's haptic ticks are recorded to this file (TRDXREC, devices/recording.hpp) with the
    /// session spec, so `tridex replay FILE` rebuilds the same model.
    std::string record;
    /// When set, the final model is saved to this file (.tdx) after the session; `tridex demo --workpiece FILE` or
    /// a scene's workpiece.model starts a session from it.
    std::string save;
    /// The session journal (`tridex recover FILE` rebuilds the model from it); "" = <out>/session.tdj.
    std::string journal;
    bool no_journal = false;  ///< --no-journal: write no journal
    /// Wall time between checkpoint models written next to the journal while the model changes, s (0 = none).
    double checkpoint_s = 120.0;
    /// The undo history's memory budget, MiB (SessionSpec::history_budget_bytes), 1..1048576 as the demo's; unset =
    /// the scene's (256 MiB).
    std::optional<double> history_mib;
    /// --keep-islands: keep the specks a cut leaves floating (SessionSpec::keep_islands; default: removed).
    bool keep_islands = false;
    /// --shared-haptic-cpu: the haptic loop's thread shares its CPU with the drawing thread
    /// (SessionSpec::reserve_haptic_cpu false; default: a CPU set aside once SCHED_FIFO is granted).
    bool shared_haptic_cpu = false;
    /// The Novint Falcon firmware file from the user's own installation (the `falcon` driver loads it when the
    /// Falcon has none running); "" = the scene's device.firmware.
    std::string falcon_firmware;
    /// A device whose link can be sealed (net): the key file, or the name of the environment variable holding the
    /// passphrase; "" = the scene's device.key_file / device.passphrase_env.
    std::string key_file;
    std::string passphrase_env;  ///< see key_file
    /// A saved model (.tdx) the session starts from instead of the scene's workpiece (as a scene's workpiece.model and
    /// `demo --workpiece`); "" = the scene's.
    std::string workpiece;
    std::string mesh;               ///< --mesh: the workpiece mesh instead of the scene's (placed as the scene's); "" = the scene's
    /// A cluster config (app/session/cluster/cluster_config.hpp): run under mpirun, rank 0 runs the session and the
    /// other ranks draw the wall's viewports; "" = one machine.
    std::string cluster;
    /// A wall without mpirun (docs/cluster.md): rank 0 listens on [ADDR:]PORT for its render ranks
    /// (--cluster-listen), or this process is render rank cluster_rank and connects to rank 0 at HOST:PORT
    /// (--cluster-connect, --rank); render ranks may then join a running wall or take a failed one's place.
    std::string cluster_listen;
    std::string cluster_connect;  ///< see cluster_listen
    int cluster_rank = 0;         ///< see cluster_listen: 1..K with --cluster-connect
    /// A shared session (docs/shared.md): host it, listening on [ADDR:]PORT (--host), or join the host at HOST:PORT
    /// (--join); "" = none. Either needs the session's key: a key file or the name of an environment variable holding
    /// its passphrase (--shared-key-file, --shared-passphrase-env).
    std::string host;
    std::string join;                   ///< see host
    std::string shared_key_file;        ///< see host
    std::string shared_passphrase_env;  ///< see host
    std::string site_name;              ///< --name: the person, as the others in a shared session see them
    /// Called on the frame thread after every frame (a monitor such as `bench --soak`); it must return quickly, as
    /// its time is the next frame's. Empty = none. Not a command-line option.
    std::function<void(const RunFrameProbe&)> frame_probe;
};

}  // namespace tridex::app
