// app/session/run/run_session.cpp - `tridex run`: its options checked and merged with the scene (the session itself:
// app/session/run/run_pipeline.cpp).
#include "app/session/run/run_session.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "app/input/dtrack_head.hpp"
#include "app/input/dtrack_wand.hpp"
#include "app/session/view/frame_budget.hpp"
#include "app/session/view/tile_view.hpp"
#include "app/session/run/run_sculpt.hpp"
#include "app/support/output_dir.hpp"
#include "core/error.hpp"
#include "core/symmetry.hpp"
#include "core/format.hpp"
#include "devices/net/enet_link.hpp"
#include "devices/net/link_wire.hpp"
#include "renderer/camera/display_config.hpp"

namespace tridex::app {

namespace {

namespace fs = std::filesystem;

// `--device TEXT` over the scene's device: a driver (NAME, NAME:ADDRESS) or a profile of the simulated hand.
void apply_device_option(const std::string& text, RunScene& scene) {
    const devices::DeviceRegistry& registry = devices::builtin_registry();
    const devices::DeviceChoice c = registry.choose(text, "--device");
    const devices::DriverInfo& d = registry.info(c.driver);
    scene.spec.device_driver = c.driver;
    if (!c.profile.empty()) scene.spec.device = c.profile;
    if (d.caps.input == devices::InputKind::kRemote) {
        std::string host;
        std::uint16_t port = 0;
        devices::net::split_host_port(c.address, "--device " + text, host, port);
        scene.spec.device_serial = c.address;
    } else if (d.caps.input == devices::InputKind::kTracked) {
        parse_tracked_tool_address(d, c.address, scene.tracked_port, scene.tracked_id);
    }
}

// --haptic-rendering, --key-file and --passphrase-env over the scene's, for the drivers whose capabilities read them.
void apply_remote_options(const RunOptions& o, const devices::DriverCapabilities& caps, SessionSpec& spec) {
    if (!o.haptic_rendering.empty()) {
        if (caps.input != devices::InputKind::kRemote)
            throw Error("--haptic-rendering " + o.haptic_rendering + ": only with --device net:HOST:PORT (a device server)");
        (void)devices::net::rendering_mode_from(o.haptic_rendering);  // "... is not distributed or local"
        spec.haptic_rendering = o.haptic_rendering;
    }
    if (!o.key_file.empty() || !o.passphrase_env.empty()) {  // replacing the scene's key
        if (!caps.seals_link)
            throw Error(std::string(o.key_file.empty() ? "--passphrase-env" : "--key-file") +
                        ": only with --device net:HOST:PORT (a device server whose link is sealed)");
        spec.device_key_file = o.key_file;
        spec.device_passphrase_env = o.passphrase_env;
    }
}

// --lod NAME (lod_choice), its errors naming the option.
LodChoice run_lod(const std::string& name) {
    try {
        return lod_choice(name);
    } catch (const Error& e) {
        throw Error(std::string("--lod: ") + e.what());
    }
}

}  // namespace

RunSetup resolve_run(const RunOptions& o) {
    RunSetup s;
    s.display = parse_display_kind(o.display);
    if (o.frames < 0) throw Error("--frames: must be >= 0, got " + std::to_string(o.frames));
    if (!std::isfinite(o.seconds) || o.seconds < 0.0 || o.seconds > 86400.0)
        throw Error("--seconds: must be between 0 and 86400, got " + format_number(o.seconds));
    s.frames = o.frames;
    s.seconds = o.seconds;
    s.out = o.out;
    prepare_output_dir(s.out, "--out");
    s.validate = o.validate;
    s.cpu = o.cpu;
    s.gpu = o.gpu;
    s.cpu_contour = o.cpu_contour;
    s.gpu_contour = o.gpu_contour;
    s.gpu_clay = o.gpu_clay;
    if (s.cpu_contour && s.gpu_contour) throw Error("--cpu-contour, --gpu-contour: choose one");
    check_backend_request({backend_mode(s.cpu, s.gpu), s.gpu_contour, s.gpu_clay});  // before any window or scene
    s.pace = o.pace;
    s.early_frames = o.early_frames;
    s.items = o.items;
    s.overlay_stats = o.overlay_stats;
    s.test_pattern = o.test_pattern;
    s.tiles = o.tiles;
    s.cull = o.cull;
    const LodChoice lod = run_lod(o.lod);
    s.lod = lod.on;
    s.coarse_groups_from_cells = lod.coarse_groups_from_cells;
    if (o.startup != "coarse" && o.startup != "full")
        throw Error("--startup: must be coarse or full, got '" + o.startup + "'");
    s.coarse_first = o.startup == "coarse";
    if (o.stroke_contour != "coarse" && o.stroke_contour != "full")
        throw Error("--stroke-contour: must be coarse or full, got '" + o.stroke_contour + "'");
    s.stroke_coarse = o.stroke_contour == "coarse";
    if (!o.ao.empty() && o.ao != "on" && o.ao != "off") throw Error("--ao: must be on or off, got '" + o.ao + "'");
    s.record = o.record;
    if (!s.record.empty()) check_output_file(s.record, "--record");
    s.save = o.save;
    if (!s.save.empty()) check_output_file(s.save, "--save");
    s.journal = o.no_journal ? "" : o.journal.empty() ? (fs::path(s.out) / "session.tdj").string() : o.journal;
    // A test pattern checks the wall: it carves nothing, so it keeps no journal (and writes no mesh).
    if (o.test_pattern) {
        if (!o.journal.empty()) throw Error("--journal, --test-pattern: a test pattern carves nothing to journal");
        s.journal.clear();
    }
    if (!(o.checkpoint_s >= 0.0 && o.checkpoint_s <= 86400.0))
        throw Error("--checkpoint-s: must be between 0 (none) and 86400, got " + format_number(o.checkpoint_s));
    s.checkpoint_s = o.checkpoint_s;
    s.frame_probe = o.frame_probe;
    if (!o.journal.empty() && o.no_journal) throw Error("--journal, --no-journal: choose one");
    if (!o.journal.empty()) check_output_file(o.journal, "--journal");
    s.scene = load_run_scene(o.scene);
    if (!o.mesh.empty()) {  // a mesh of the user's own in the scene's place (its centre, size and resolution)
        std::error_code ec;
        if (!fs::is_regular_file(o.mesh, ec)) throw Error("--mesh: no such file: " + o.mesh);
        if (!o.workpiece.empty()) throw Error("--mesh, --workpiece: choose one");
        s.scene.spec.mesh_path = fs::absolute(o.mesh).lexically_normal().string();
        s.scene.spec.model_path.clear();
    }
    if (!o.workpiece.empty()) {  // a saved model decides the lattice, the placement and the resolution
        std::error_code ec;
        if (!fs::is_regular_file(o.workpiece, ec)) throw Error("--workpiece: no such file: " + o.workpiece);
        s.scene.spec.model_path = fs::absolute(o.workpiece).lexically_normal().string();
        s.scene.spec.mesh_path.clear();
    }
    check_distinct_files({{"--out's sculpted.ply", (fs::path(s.out) / "sculpted.ply").string()},
                          {"--out's report.json", (fs::path(s.out) / "report.json").string()},
                          {s.save.empty() ? "the Ctrl+S model (--out's model.tdx)" : "--save",
                           s.save.empty() ? (fs::path(s.out) / "model.tdx").string() : s.save},
                          {"--record", s.record},
                          {o.journal.empty() ? "the journal (--out's session.tdj)" : "--journal", s.journal}},
                         {{"the scene", o.scene},
                          {"the scene's workpiece model", s.scene.spec.model_path},
                          {"the scene's workpiece mesh", s.scene.spec.model_path.empty() ? s.scene.spec.mesh_path : ""}});
    if (o.history_mib) {  // the same range as the demo's
        if (!(*o.history_mib >= 1.0 && *o.history_mib <= 1048576.0))
            throw Error("--history-mib: must be between 1 and 1048576, got " + format_number(*o.history_mib));
        s.scene.spec.history_budget_bytes = static_cast<std::size_t>(*o.history_mib * 1048576.0);
    }
    if (o.keep_islands) s.scene.spec.keep_islands = true;
    if (o.shared_haptic_cpu) s.scene.spec.reserve_haptic_cpu = false;
    if (!o.falcon_firmware.empty()) s.scene.spec.device_firmware = o.falcon_firmware;
    if (!o.display_config.empty()) s.scene.display = renderer::load_display_config(o.display_config);
    if (!o.stereo.empty()) {
        try {
            s.scene.display.stereo = renderer::parse_stereo_output(o.stereo);
        } catch (const Error& e) {
            throw Error(std::string("--stereo: ") + e.what());
        }
    }
    if (o.head.rfind("dtrack:", 0) == 0) {
        s.scene.head = HeadMode::kDTrack;
        parse_dtrack_head_option(o.head, s.scene.dtrack_port, s.scene.dtrack_body);
    } else if (!o.head.empty()) {
        s.scene.head = parse_head_mode(o.head, "--head");
        if (s.scene.head == HeadMode::kScripted && s.scene.head_waypoints.empty())
            throw Error("--head scripted: the scene " + s.scene.source + " has no head.waypoints");
    }
    if (o.wand == "none") {
        s.scene.wand_dtrack = false;
    } else if (!o.wand.empty()) {
        s.scene.wand_dtrack = true;
        parse_dtrack_wand_option(o.wand, s.scene.wand_port, s.scene.wand_flystick);
    }
    s.swap_eyes = o.swap_eyes || s.scene.display.swap_eyes;
    s.ao = o.ao.empty() ? s.scene.display.ambient_occlusion : o.ao == "on";
    if (o.ao_sculpting != "on" && o.ao_sculpting != "off" && o.ao_sculpting != "auto")
        throw Error("--ao-while-sculpting: must be on, off or auto, got '" + o.ao_sculpting + "'");
    s.ao_sculpting = o.ao_sculpting;
    // Refuses a bad value before any window opens.
    (void)FrameBudget(FrameBudgetOptions{o.frame_target_ms, o.min_render_scale, o.max_lod_px});
    s.frame_target_ms = o.frame_target_ms;
    s.min_render_scale = o.min_render_scale;
    s.max_lod_px = o.max_lod_px;
    if (!o.monitor.empty()) {
        const bool digits = std::all_of(o.monitor.begin(), o.monitor.end(), [](unsigned char c) { return std::isdigit(c); });
        if (digits && o.monitor.size() < 4)
            s.monitor_index = std::stoi(o.monitor);
        else
            s.monitor_name = o.monitor;
    }
    // The hand at a window is the person's: with no device named, the mouse (the scripted hand is --device simulated).
    if (!o.device.empty()) apply_device_option(o.device, s.scene);
    else if (!s.scene.device_named && s.display != DisplayKind::kOffscreen) apply_device_option("mouse", s.scene);
    const devices::DriverInfo& driver_info = devices::builtin_registry().info(s.scene.spec.device_driver);
    const devices::DriverCapabilities& caps = driver_info.caps;
    apply_remote_options(o, caps, s.scene.spec);
    if (caps.input == devices::InputKind::kRemote && s.scene.spec.haptic_rendering == "local" && !s.scene.objects.empty())
        throw Error(s.scene.source + ": field 'objects': scene objects are felt by the session's own contact loop; a "
                    "device server renders only the workpiece in local haptic rendering: use distributed rendering");
    if (devices::person_moves_hand(caps.input)) s.scene.has_stroke = false;  // the person is the hand
    if (!o.symmetry.empty()) s.scene.spec.symmetry = to_string(parse_symmetry(o.symmetry, "--symmetry"));
    if (s.test_pattern) s.scene.spec.op = "none";  // the tool still follows its device, touching only
    // The wand is a Flystick: a tracked tool may not be the same one.
    if (caps.input == devices::InputKind::kTracked && caps.target_kind == "Flystick" && s.scene.wand_dtrack &&
        s.scene.wand_port == s.scene.tracked_port && s.scene.wand_flystick == s.scene.tracked_id)
        throw Error("--device " + driver_info.name + ": Flystick " + std::to_string(s.scene.tracked_id) +
                    " navigates the scene already (--wand); give the tool another Flystick");
    s.bindings = default_bindings(driver_info.name, caps);
    if (!s.scene.bindings.empty()) apply_bindings(nlohmann::json::parse(s.scene.bindings), s.scene.source, s.bindings);
    if (!o.bindings.empty()) s.bindings = load_bindings(o.bindings, driver_info.name, caps);
    if (!s.scene.wand_dtrack) s.bindings.wand.buttons.clear();  // no wand: nothing of it to read
    // The scripted participant's path.
    const bool scripted_study = s.scene.study.enabled && caps.input == devices::InputKind::kScripted;
    if (s.display == DisplayKind::kOffscreen && s.frames == 0 && s.seconds == 0.0 && !s.scene.has_stroke &&
        s.scene.cursor.empty() && !scripted_study)
        throw Error("--frames/--seconds: an offscreen run of a scene without a stroke or a scripted cursor needs "
                    "--frames N or --seconds S");
    return s;
}

}  // namespace tridex::app
