// app/main.cpp - the `tridex` command line.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <exception>
#include <new>
#include <vector>

#include "bench/bench_accuracy.hpp"
#include "bench/bench_filter.hpp"
#include "bench/bench_input.hpp"
#include "bench/bench_haptics.hpp"
#include "bench/bench_link.hpp"
#include "bench/bench_persistence.hpp"
#include "bench/bench_render.hpp"
#include "bench/bench_sculpt.hpp"
#include "bench/bench_session.hpp"
#include "bench/bench_undo.hpp"
#include "app/demo.hpp"
#include "app/device_lost.hpp"
#include "app/device_server_cmd.hpp"
#include "app/devices_cmd.hpp"
#include "app/elastic_demo.hpp"
#include "app/export_cmd.hpp"
#include "app/recover.hpp"
#include "app/replay.hpp"
#include "app/run_cli.hpp"
#include "app/stop_signal.hpp"
#include "app/study/study_cli.hpp"
#include "core/error.hpp"

namespace {

// Mesa's Vulkan drivers (lavapipe) want XDG_RUNTIME_DIR; when the session has none (a plain ssh or
// CI shell), give them a private 0700 folder of this user's instead of letting them warn or fail.
void ensure_runtime_dir() {
    if (std::getenv("XDG_RUNTIME_DIR")) return;
    const std::string dir = "/tmp/tridex-runtime-" + std::to_string(getuid());
    struct stat st {};
    if (mkdir(dir.c_str(), 0700) == 0 || (stat(dir.c_str(), &st) == 0 && S_ISDIR(st.st_mode) && st.st_uid == getuid()))
        setenv("XDG_RUNTIME_DIR", dir.c_str(), 0);
}

}  // namespace

int main(int argc, char** argv) {
    ensure_runtime_dir();
    CLI::App cli{"tridex: immersive virtual sculpting with force feedback on a tri-dexel workpiece"};
    cli.require_subcommand(1);

    tridex::app::DemoOptions demo;
    double tool_radius_mm = demo.tool_radius_m * 1e3;
    CLI::App* demo_cmd = cli.add_subcommand(
        "demo", "Carve the workpiece with a scripted stroke under the 1 kHz haptic loop and write stereo frames");
    auto* demo_mesh = demo_cmd->add_option("--mesh", demo.mesh, "Workpiece mesh (OFF, OBJ, PLY, STL; closed); default: the bundled bunny")
        ->check(CLI::ExistingFile);
    auto* demo_resolution = demo_cmd->add_option("--resolution", demo.resolution, "Lattice cells along the workpiece's longest side")
        ->capture_default_str();
    demo_cmd->add_option("--seconds", demo.seconds, "Length of the scripted stroke, s")->capture_default_str();
    demo_cmd->add_option("--out", demo.out, "Output folder")->capture_default_str();
    demo_cmd->add_option("--width", demo.width, "Per-eye image width, px")->capture_default_str();
    demo_cmd->add_option("--height", demo.height, "Per-eye image height, px")->capture_default_str();
    demo_cmd->add_option("--tool-radius-mm", tool_radius_mm, "Tool radius (ball or flat-end mill), mm")->capture_default_str();
    demo_cmd->add_option("--tool", demo.tool,
                         "Tool shape: ball, flat_end (a flat-end mill, shank up the tool axis) or mesh (--tool-mesh)")
        ->capture_default_str();
    double tool_length_mm = demo.tool_length_m * 1e3;
    demo_cmd->add_option("--tool-length-mm", tool_length_mm, "flat_end: cylinder length, mm")->capture_default_str();
    demo_cmd->add_option("--tool-mesh", demo.tool_mesh,
                         "mesh: the tool's closed mesh file (+y its axis; its tip, the lowest point, is the HIP)");
    double tool_size_mm = demo.tool_size_m * 1e3;
    demo_cmd->add_option("--tool-size-mm", tool_size_mm, "mesh: longest side of the tool mesh after scaling, mm")
        ->capture_default_str();
    demo_cmd->add_flag("--validate", demo.validate, "Enable the Vulkan validation layer");
    std::string demo_ao = "on";
    demo_cmd->add_option("--ao", demo_ao, "on | off: ambient occlusion in the images (cuts darker, edges brighter)")
        ->check(CLI::IsMember({"on", "off"}))
        ->capture_default_str();
    demo_cmd->add_option("--points", demo.points, "Contact points: 1 ball HIP, 2 wand top/bottom, 3..64 interaction mesh")
        ->capture_default_str();
    demo_cmd
        ->add_option("--device", demo.device,
                     "Simulated device profile: omni, wand (5-DOF) or 6dof; or falcon (a Novint Falcon over USB) or "
                     "falcon-emulator (the Falcon driver over an emulated Falcon); or net:HOST:PORT (a device served by "
                     "`tridex device-server`)")
        ->capture_default_str();
    demo_cmd
        ->add_option("--haptic-rendering", demo.haptic_rendering,
                     "With --device net:HOST:PORT: distributed (this session computes the force) or local (the device "
                     "server runs the contact loop next to the device)")
        ->capture_default_str()
        ->check(CLI::IsMember({"distributed", "local"}));
    demo_cmd->add_option(
        "--falcon-firmware", demo.falcon_firmware,
        "Novint Falcon firmware FILE from your own installation (the falcon driver loads it; never shipped)");
    demo_cmd->add_option("--workspace", demo.workspace, "Workspace technique: peng_moving, scaling, clutching or bubble")
        ->capture_default_str();
    demo_cmd->add_option("--static-friction", demo.static_friction, "Coulomb static friction coefficient")->capture_default_str();
    demo_cmd->add_option("--dynamic-friction", demo.dynamic_friction, "Coulomb dynamic friction coefficient")->capture_default_str();
    bool no_cutting = false;
    demo_cmd->add_flag("--no-cutting-force", no_cutting, "No reaction force against the tool's advance while carving");
    demo_cmd->add_option("--record", demo.record, "Record the session to FILE (TRDXREC, thesis Table 3 fields)");
    demo_cmd->add_option("--save", demo.save, "Save the final model to FILE.tdx (tri-dexel model file)");
    demo_cmd->add_option("--workpiece", demo.workpiece,
                         "Start from a saved model FILE.tdx (from --save) instead of a mesh; it decides the resolution")
        ->check(CLI::ExistingFile)
        ->excludes(demo_mesh)
        ->excludes(demo_resolution);
    auto* demo_journal = demo_cmd->add_option("--journal", demo.journal,
                                              "Session journal FILE (default: OUT/session.tdj; `tridex recover FILE` rebuilds the model)");
    demo_cmd->add_flag("--no-journal", demo.no_journal, "Write no session journal")->excludes(demo_journal);
    demo_cmd->add_option("--checkpoint-s", demo.checkpoint_s,
                         "Seconds between checkpoint models written next to the journal while sculpting (0 = none)")
        ->capture_default_str();
    demo_cmd->add_option("--history-mib", demo.history_mib, "Memory for undo, MiB (oldest strokes dropped first)")
        ->capture_default_str();
    demo_cmd
        ->add_option("--op", demo.op,
                     "What the tool does: subtract, union (add material), paint, push, smooth or pull (clay: move material)")
        ->capture_default_str();
    demo_cmd->add_option("--material", demo.material, "Palette id 1..7 that union adds and paint sets")->capture_default_str();
    demo_cmd->add_flag("--cpu", demo.cpu, "Sculpt on the CPU reference instead of the GPU (Vulkan compute)");
    auto* demo_cpu_contour = demo_cmd->add_flag("--cpu-contour", demo.cpu_contour,
                       "Contour on the CPU even when sculpting on the GPU (default: GPU contouring, drawn with indirect "
                       "draws, on a real GPU; CPU contouring on a CPU Vulkan such as lavapipe)");
    demo_cmd->add_flag("--gpu-contour", demo.gpu_contour,
                       "Contour on the GPU even on a CPU Vulkan implementation (lavapipe), where it is slower")
        ->excludes(demo_cpu_contour);
    demo_cmd->add_flag("--gpu-clay", demo.gpu_clay,
                       "Push, smooth and pull on the GPU clay kernel even on a CPU Vulkan implementation (lavapipe), "
                       "where the CPU reference is faster (same result bit for bit)");

    bool demo_elastic = false;
    std::string elastic_scene;
    demo_cmd->add_flag("--elastic", demo_elastic,
                       "Press an elastic object (a squeeze ball) in steps and let go: its drawn surface dents within the "
                       "radius of influence and springs back; the force comes from the undeformed surface");
    demo_cmd->add_option("--scene", elastic_scene,
                         "--elastic: the scene file (objects, tool, press); default: assets/squeeze_ball_scene.json")
        ->check(CLI::ExistingFile);

    tridex::app::OutputOptions replay_out;
    replay_out.out = "out/replay";
    std::string replay_file;
    CLI::App* replay_cmd = cli.add_subcommand("replay", "Sculpt a recorded session again and write the demo's outputs");
    replay_cmd->add_option("FILE", replay_file, "Recording made with `tridex demo --record FILE`")->required()->check(CLI::ExistingFile);
    replay_cmd->add_option("--out", replay_out.out, "Output folder")->capture_default_str();
    replay_cmd->add_option("--width", replay_out.width, "Per-eye image width, px")->capture_default_str();
    replay_cmd->add_option("--height", replay_out.height, "Per-eye image height, px")->capture_default_str();
    replay_cmd->add_flag("--validate", replay_out.validate, "Enable the Vulkan validation layer");
    tridex::app::SculptOptions replay_sculpt;
    replay_cmd->add_flag("--cpu", replay_sculpt.cpu, "Sculpt on the CPU reference instead of the GPU (Vulkan compute)");
    auto* replay_cpu_contour = replay_cmd->add_flag("--cpu-contour", replay_sculpt.cpu_contour,
                                                    "Contour on the CPU even when sculpting on the GPU (as for demo)");
    replay_cmd->add_flag("--gpu-contour", replay_sculpt.gpu_contour,
                         "Contour on the GPU even on a CPU Vulkan implementation (lavapipe), where it is slower")
        ->excludes(replay_cpu_contour);
    replay_cmd->add_flag("--gpu-clay", replay_sculpt.gpu_clay,
                         "Push, smooth and pull on the GPU clay kernel even on a CPU Vulkan implementation (lavapipe)");

    tridex::app::ExportOptions export_opt;
    CLI::App* export_cmd =
        cli.add_subcommand("export", "Contour a saved model (.tdx) and write it as a closed mesh (STL, OBJ or PLY)");
    export_cmd->add_option("MODEL", export_opt.model, "Saved model (tridex demo/run --save FILE.tdx)")
        ->required()
        ->check(CLI::ExistingFile);
    export_cmd->add_option("OUT", export_opt.out, "Mesh file: .stl (binary), .obj or .ply (binary, material colours)")
        ->required();
    export_cmd->add_option("--units", export_opt.units, "Units of the written coordinates: m or mm")
        ->capture_default_str()
        ->check(CLI::IsMember({"m", "mm"}));
    std::string recover_file, recover_out = "out/recover";
    CLI::App* recover_cmd = cli.add_subcommand(
        "recover", "Rebuild a session's model from its journal (after a crash or power loss): sculpted.ply, report.json");
    recover_cmd->add_option("JOURNAL", recover_file, "Session journal (OUT/session.tdj of demo or run, or their --journal FILE)")
        ->required()
        ->check(CLI::ExistingFile);
    recover_cmd->add_option("--out", recover_out, "Output folder")->capture_default_str();

    tridex::app::HapticsBenchOptions hbench;
    bool bench_haptics = false;
    CLI::App* bench_cmd = cli.add_subcommand("bench", "Benchmarks that print tables and write JSON (numbers, not pass/fail)");
    bench_cmd->add_flag("--haptics", bench_haptics,
                        "Haptic tick compute time against resolution (128..1024) and contact points (1, 2, 16, 64)");
    bool bench_render = false;
    tridex::app::RenderBenchOptions rbench;
    bench_cmd->add_flag("--render", bench_render,
                        "Offscreen stereo frame time per pass at 1280x720 and 1920x1080, bunny at 256 and 512 cells, "
                        "with and without per-tile levels of detail and tile culling");
    std::vector<int> render_n;
    bench_cmd->add_option("--render-n", render_n, "With --render: run only these N (16..1024), e.g. --render-n 256")
        ->delimiter(',')
        ->check(CLI::Range(16, 1024));
    std::vector<std::string> render_ao;
    bench_cmd->add_option("--render-ao", render_ao,
                          "With --render: ambient occlusion settings to time, interleaved (default on,off)")
        ->delimiter(',')
        ->check(CLI::IsMember({"on", "off"}));
    std::vector<std::string> render_size;
    bench_cmd->add_option("--render-size", render_size,
                          "With --render: per-eye image sizes WxH (default 1280x720,1920x1080)")
        ->delimiter(',');
    bool bench_sculpt = false;
    bench_cmd->add_flag("--sculpt", bench_sculpt,
                        "Swept-Boolean throughput and latency: CPU 1 thread / all cores, GPU per segment / batched, "
                        "N = 256, 512, 1024, tool radius 2 and 8 cells");
    std::vector<int> sculpt_n;
    bench_cmd->add_option("--sculpt-n", sculpt_n, "With --sculpt: run only these N (24..2048), e.g. --sculpt-n 256,512")
        ->delimiter(',');
    std::vector<double> sculpt_radius;
    bench_cmd->add_option("--sculpt-radius", sculpt_radius,
                          "With --sculpt: run only these tool radii, cells ((0, N/8]), e.g. --sculpt-radius 8")
        ->delimiter(',');
    std::vector<std::string> sculpt_paths;
    bench_cmd->add_option("--sculpt-paths", sculpt_paths,
                          "With --sculpt: run only these paths (cpu-1t, cpu, gpu, gpu-batched; clay-push, clay-smooth, gpu-clay-push, "
                          "gpu-clay-smooth only when named), "
                          "e.g. --sculpt-paths cpu,gpu-batched")
        ->delimiter(',');
    bool bench_session = false;
    bench_cmd->add_flag("--session", bench_session,
                        "Whole sessions through the session runtime (the demo's stroke on the bunny, N = 256 and 512, "
                        "CPU and GPU paths): haptic period and tick time, sculpt step times");
    std::vector<int> session_n;
    bench_cmd->add_option("--session-n", session_n, "With --session: run only these N, e.g. --session-n 256")
        ->delimiter(',');
    bool session_journal_off = false;
    bench_cmd->add_flag("--session-journal-off", session_journal_off,
                        "With --session: also run each session without its journal (--no-journal), for comparison");
    bool bench_persistence = false;
    bench_cmd->add_flag("--persistence", bench_persistence,
                        "Model file (.tdx) save and load time, file size against memory: bunny at N = 256 and 512, carved");
    bool bench_undo = false;
    bench_cmd->add_flag("--undo", bench_undo,
                        "Per-stroke undo and redo latency of the sculpt thread (write back, active surface, re-contour): "
                        "bunny at N = 256 and 512, CPU and GPU paths");
    std::vector<int> undo_n;
    bench_cmd->add_option("--undo-n", undo_n, "With --undo: run only these N, e.g. --undo-n 256")->delimiter(',');
    std::vector<std::string> undo_paths;
    bench_cmd->add_option("--undo-paths", undo_paths, "With --undo: run only these paths (cpu, gpu)")->delimiter(',');
    bool bench_link = false;
    bench_cmd->add_flag("--link", bench_link,
                        "Local vs distributed haptic rendering through an injected-latency, lossy link (link_bench.json)");
    bool bench_filter = false;
    bench_cmd->add_flag("--filter", bench_filter,
                        "EWMA force filter constant: chatter amplitude vs lag with encoder quantisation and noise "
                        "(filter_bench.json, filter_bench.png)");
    bool bench_input = false;
    bench_cmd->add_flag("--input", bench_input,
                        "Tracked input: DTrack ASCII parse cost per datagram and the receiver's hand-off latency over "
                        "loopback (input_bench.json)");
    bool bench_accuracy = false;
    bench_cmd->add_flag("--accuracy", bench_accuracy,
                        "Run time against error on stroke programs with an exact answer (box workpiece, N = 64, 128, 256, 512): "
                        "tridex CPU 1 thread, CPU all cores and GPU, and an OpenVDB level-set peer at the same N when built in");
    std::vector<int> accuracy_n;
    bench_cmd->add_option("--accuracy-n", accuracy_n, "With --accuracy: run only these N (16..1024), e.g. --accuracy-n 64,256")
        ->delimiter(',');
    std::vector<std::string> accuracy_programs;
    bench_cmd->add_option("--accuracy-programs", accuracy_programs,
                          "With --accuracy: run only these programs (pocket, random_ball, flat_random, plunge, union, paint)")
        ->delimiter(',');
    std::vector<std::string> accuracy_paths;
    bench_cmd->add_option("--accuracy-paths", accuracy_paths, "With --accuracy: run only these paths (cpu-1t, cpu, gpu, openvdb)")
        ->delimiter(',')
        ->check(CLI::IsMember({"cpu-1t", "cpu", "gpu", "openvdb"}));
    double accuracy_offset = 0.0;
    bench_cmd->add_option("--accuracy-offset", accuracy_offset,
                          "With --accuracy: lattice origin shift in cells, [0, 1) (0 = cube faces on lattice nodes)")
        ->capture_default_str();
    int accuracy_dump = 0;
    bench_cmd->add_option("--accuracy-dump", accuracy_dump,
                          "With --accuracy: print the K worst vertices of each tridex cpu-1t run with their cells' crossings and "
                          "normals against the exact solid")
        ->check(CLI::Range(0, 1000));
    bench_cmd->add_option("--frames", rbench.frames, "Timed frames per render row")->capture_default_str()->check(CLI::Range(1, 1000));
    bench_cmd->add_option("--out", hbench.out, "Output folder")->capture_default_str();
    bench_cmd->add_option("--mesh", hbench.mesh, "Workpiece mesh; default: the bundled bunny")->check(CLI::ExistingFile);
    bench_cmd->add_option("--ticks", hbench.ticks, "Timed ticks per row")->capture_default_str()->check(CLI::Range(100, 10000000));

    bool devices_as_json = false;
    CLI::App* devices_cmd =
        cli.add_subcommand("devices", "List the haptic device drivers and the known hardware that is plugged in");
    devices_cmd->add_flag("--json", devices_as_json, "Print a JSON list of objects (name, driver, dof, detected, ...)");

    tridex::app::DeviceServerOptions server;
    CLI::App* server_cmd = cli.add_subcommand(
        "device-server", "Own a haptic device on this machine and serve it to a session elsewhere (--device net:HOST:PORT)");
    server_cmd->add_option("--device", server.device, "Driver of the served device: simulated, falcon, falcon-emulator")
        ->capture_default_str();
    server_cmd->add_option("--profile", server.profile, "simulated: device profile omni, wand, 6dof or falcon")->capture_default_str();
    server_cmd->add_option("--listen", server.listen, "HOST:PORT to listen on (0.0.0.0:PORT = every interface; port 0 = a free one, printed)")
        ->capture_default_str();
    server_cmd->add_option("--seconds", server.seconds, "Stop after S seconds (0 = until Ctrl+C)")->capture_default_str();
    server_cmd->add_flag("--once", server.once, "Stop when the first session ends");
    server_cmd->add_option("--falcon-firmware", server.falcon_firmware, "falcon: the firmware FILE from your own installation");
    server_cmd->add_option("--mesh", server.mesh, "simulated, falcon-emulator: the hand plays the demo stroke over this mesh")
        ->check(CLI::ExistingFile);
    server_cmd->add_option("--stroke-seconds", server.stroke_seconds, "simulated, falcon-emulator: the stroke's length (the session's --seconds)")
        ->capture_default_str();

    tridex::app::RunOptions run;
    CLI::App* run_cmd = tridex::app::add_run_command(cli, run);
    tridex::app::study::StudyCommand study;
    CLI::App* study_cmd = tridex::app::study::add_study_command(cli, study);

    // A first word that names no command: say so and list the commands (CLI11 would only ask for a subcommand).
    if (argc >= 2 && argv[1][0] == '-') {
        const std::string first = argv[1];
        if (first != "-h" && first != "--help" && first != "--help-all" && first != "--version") {
            std::fprintf(stderr, "tridex: unknown option '%s': a command comes first (see tridex --help)\n", argv[1]);
            return 2;
        }
    } else if (argc >= 2) {
        std::string names;
        bool known = false;
        for (const CLI::App* sub : cli.get_subcommands([](CLI::App*) { return true; })) {
            names += (names.empty() ? "" : ", ") + sub->get_name();
            known = known || sub->get_name() == argv[1];
        }
        if (!known) {
            std::fprintf(stderr, "tridex: unknown command '%s'; the commands are %s (see tridex --help)\n", argv[1],
                         names.c_str());
            return 2;
        }
    }
    cli.set_version_flag("--version", "tridex " TRIDEX_VERSION);
    try {
        cli.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return cli.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return cli.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return cli.exit(e);
    } catch (const CLI::ParseError& e) {
        // Every bad input exits 2 with one line (README): CLI11's message, and where to look.
        std::fprintf(stderr, "tridex: %s (see tridex %s--help)\n", e.what(),
                     cli.get_subcommands().empty() ? "" : (cli.get_subcommands().front()->get_name() + " ").c_str());
        return 2;
    }
    tridex::app::install_stop_handlers();  // SIGINT/SIGTERM end a session cleanly, then exit 128 + signal
    try {
        if (*demo_cmd && (demo_elastic || demo_cmd->count("--scene") > 0)) {
            if (!demo_elastic) throw tridex::Error("--scene: only with --elastic");
            for (const CLI::Option* opt : demo_cmd->get_options()) {
                const std::string name = opt->get_name();
                if (opt->count() > 0 && name != "--elastic" && name != "--scene" && name != "--out" &&
                    name != "--width" && name != "--height" && name != "--validate" && name != "--help")
                    throw tridex::Error("--elastic: " + name +
                                        " does not apply (the scene file sets the objects, the tool and the press)");
            }
            tridex::app::ElasticDemoOptions elastic;
            elastic.scene = elastic_scene;
            if (demo_cmd->count("--out") > 0) elastic.out = demo.out;
            elastic.width = demo.width;
            elastic.height = demo.height;
            elastic.validate = demo.validate;
            tridex::app::run_elastic_demo(elastic);
        } else if (*demo_cmd) {
            // Options that only one tool or device reads are refused with the others rather than ignored.
            if (demo_cmd->count("--tool-length-mm") > 0 && demo.tool != "flat_end")
                throw tridex::Error("--tool-length-mm: only with --tool flat_end");
            if (!demo.falcon_firmware.empty() && demo.device != "falcon" && demo.device != "falcon-emulator")
                throw tridex::Error("--falcon-firmware: only with --device falcon or falcon-emulator");
            demo.tool_radius_m = tool_radius_mm * 1e-3;
            demo.tool_length_m = tool_length_mm * 1e-3;
            demo.tool_size_m = tool_size_mm * 1e-3;
            demo.cutting = !no_cutting;
            demo.ao = demo_ao == "on";
            tridex::app::run_demo(demo);
        }
        if (*replay_cmd) tridex::app::run_replay(replay_file, replay_out, replay_sculpt);
        if (*recover_cmd) tridex::app::run_recover(recover_file, recover_out);
        if (*run_cmd) {
            const int rc = tridex::app::run_command(run);
            return tridex::app::stop_signal() ? 128 + tridex::app::stop_signal() : rc;
        }
        if (*devices_cmd) tridex::app::run_devices(devices_as_json);
        if (*server_cmd) tridex::app::run_device_server(server);
        if (*export_cmd) tridex::app::run_export(export_opt);
        if (*study_cmd) tridex::app::study::run_study_command(study);
        if (*bench_cmd) {
            if (!bench_haptics && !bench_render && !bench_sculpt && !bench_accuracy && !bench_session && !bench_persistence &&
                !bench_undo && !bench_link && !bench_filter && !bench_input)
                throw tridex::Error("bench: choose what to measure: --haptics, --render, --sculpt, --session, --accuracy, "
                                    "--persistence, --undo, --link, --filter and/or --input");
            if (bench_input) tridex::app::run_input_bench(hbench.out);
            if (bench_link) {
                tridex::app::LinkBenchOptions lb;
                lb.out = hbench.out;
                tridex::app::run_link_bench(lb);
            }
            if (bench_filter) {
                tridex::app::FilterBenchOptions fb;
                fb.out = hbench.out;
                tridex::app::run_filter_bench(fb);
            }
            if (bench_session) {
                tridex::app::SessionBenchOptions sb;
                sb.out = hbench.out;
                if (!session_n.empty()) sb.resolutions = session_n;
                if (session_journal_off) sb.journal = {true, false};
                tridex::app::run_session_bench(sb);
            }
            if (bench_haptics) tridex::app::run_haptics_bench(hbench);
            if (bench_render) {
                rbench.out = hbench.out;
                if (!render_ao.empty()) {
                    rbench.occlusion.clear();
                    for (const std::string& a : render_ao) rbench.occlusion.push_back(a == "on");
                }
                if (!render_size.empty()) {
                    rbench.sizes.clear();
                    for (const std::string& z : render_size) rbench.sizes.push_back(tridex::app::parse_image_size(z, "--render-size"));
                }
                rbench.mesh = hbench.mesh;
                if (!render_n.empty()) rbench.resolutions = render_n;
                tridex::app::run_render_bench(rbench);
            }
            if (bench_sculpt) {
                tridex::app::SculptBenchOptions sbench;
                sbench.out = hbench.out;
                if (!sculpt_n.empty()) sbench.resolutions = sculpt_n;
                if (!sculpt_radius.empty()) sbench.radii_cells = sculpt_radius;
                if (!sculpt_paths.empty()) sbench.paths = sculpt_paths;
                tridex::app::run_sculpt_bench(sbench);
            }
            if (bench_persistence) {
                tridex::app::PersistenceBenchOptions pbench;
                pbench.out = hbench.out;
                pbench.mesh = hbench.mesh;
                tridex::app::run_persistence_bench(pbench);
            }
            if (bench_undo) {
                tridex::app::UndoBenchOptions ubench;
                ubench.out = hbench.out;
                ubench.mesh = hbench.mesh;
                if (!undo_n.empty()) ubench.resolutions = undo_n;
                if (!undo_paths.empty()) ubench.paths = undo_paths;
                tridex::app::run_undo_bench(ubench);
            }
            if (bench_accuracy) {
                tridex::app::AccuracyBenchOptions abench;
                abench.out = hbench.out;
                if (!accuracy_n.empty()) abench.resolutions = accuracy_n;
                abench.programs = accuracy_programs;
                if (!accuracy_paths.empty()) {
                    const auto has = [&](const char* p) { return std::find(accuracy_paths.begin(), accuracy_paths.end(), p) != accuracy_paths.end(); };
                    abench.cpu_one_thread = has("cpu-1t");
                    abench.cpu_all_cores = has("cpu");
                    abench.gpu = has("gpu");
                    abench.openvdb = has("openvdb");
                }
                abench.offset_cells = accuracy_offset;
                abench.dump_worst = accuracy_dump;
                tridex::app::run_accuracy_bench(abench);
            }
        }
        return tridex::app::stop_signal() ? 128 + tridex::app::stop_signal() : 0;
    } catch (const tridex::app::DeviceLostError& e) {
        std::fprintf(stderr, "tridex: %s\n", e.what());
        return 4;
    } catch (const tridex::Error& e) {
        std::fprintf(stderr, "tridex: %s\n", e.what());
        return 2;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "tridex: out of memory; lower --resolution\n");
        return 3;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "tridex: internal error: %s\n", e.what());
        return 1;
    }
}
