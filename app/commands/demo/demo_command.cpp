// app/commands/demo/demo_command.cpp - `tridex demo`: the scripted stroke (or, with --elastic, the elastic press).
#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "app/commands/command.hpp"
#include "app/commands/demo/demo.hpp"
#include "app/commands/demo/elastic_demo.hpp"
#include "core/error.hpp"
#include "core/symmetry.hpp"

namespace tridex::app {
namespace {

// What `tridex demo` parses into: the session's options, and the values given in the user's units.
struct DemoCli {
    DemoOptions demo;
    double tool_radius_mm = DemoOptions{}.tool_radius_m * 1e3;
    double tool_length_mm = DemoOptions{}.tool_length_m * 1e3;
    double tool_size_mm = DemoOptions{}.tool_size_m * 1e3;
    std::string ao = "on";
    bool no_cutting = false;
    bool elastic = false;
    std::string elastic_scene;
};

// The workpiece, the tool and the device. Returns the options that --workpiece excludes.
std::pair<CLI::Option*, CLI::Option*> declare_workpiece_tool_device(CLI::App& cmd, DemoCli& o) {
    auto* demo_mesh = cmd.add_option("--mesh", o.demo.mesh, "Workpiece mesh (OFF, OBJ, PLY, STL; closed); default: the bundled bunny")
        ->check(CLI::ExistingFile);
    auto* demo_resolution = cmd.add_option("--resolution", o.demo.resolution, "Lattice cells along the workpiece's longest side")
        ->capture_default_str();
    cmd.add_option("--seconds", o.demo.seconds, "Length of the scripted stroke, s")->capture_default_str();
    cmd.add_option("--out", o.demo.out, "Output folder")->capture_default_str();
    cmd.add_option("--width", o.demo.width, "Per-eye image width, px")->capture_default_str();
    cmd.add_option("--height", o.demo.height, "Per-eye image height, px")->capture_default_str();
    cmd.add_option("--tool-radius-mm", o.tool_radius_mm, "Tool radius (ball or flat-end mill), mm")->capture_default_str();
    cmd.add_option("--tool", o.demo.tool,
                         "Tool shape: ball, flat_end (a flat-end mill, shank up the tool axis) or mesh (--tool-mesh)")
        ->capture_default_str();
    cmd.add_option("--tool-length-mm", o.tool_length_mm, "flat_end: cylinder length, mm")->capture_default_str();
    cmd.add_option("--tool-mesh", o.demo.tool_mesh,
                         "mesh: the tool's closed mesh file (+y its axis; its tip, the lowest point, is the HIP)");
    cmd.add_option("--tool-size-mm", o.tool_size_mm, "mesh: longest side of the tool mesh after scaling, mm")
        ->capture_default_str();
    cmd.add_flag("--validate", o.demo.validate, "Enable the Vulkan validation layer");
    cmd.add_option("--ao", o.ao, "on | off: ambient occlusion in the images (cuts darker, edges brighter)")
        ->check(CLI::IsMember({"on", "off"}))
        ->capture_default_str();
    cmd.add_option("--points", o.demo.points, "Contact points: 1 ball HIP, 2 wand top/bottom, 3..64 interaction mesh")
        ->capture_default_str();
    cmd
        .add_option("--device", o.demo.device,
                     "Simulated device profile: omni, wand (5-DOF) or 6dof; or falcon (a Novint Falcon over USB) or "
                     "falcon-emulator (the Falcon driver over an emulated Falcon); or net:HOST:PORT (a device served by "
                     "`tridex device-server`)")
        ->capture_default_str();
    cmd
        .add_option("--haptic-rendering", o.demo.haptic_rendering,
                     "With --device net:HOST:PORT: distributed (this session computes the force) or local (the device "
                     "server runs the contact loop next to the device)")
        ->capture_default_str()
        ->check(CLI::IsMember({"distributed", "local"}));
    cmd.add_option(
        "--falcon-firmware", o.demo.falcon_firmware,
        "Novint Falcon firmware FILE from your own installation (the falcon driver loads it; never shipped)");
    cmd.add_option("--key-file", o.demo.key_file,
                    "With --device net:HOST:PORT: the key FILE the device server seals its link with (--key-file there)");
    cmd.add_option("--passphrase-env", o.demo.passphrase_env,
                    "With --device net:HOST:PORT: the environment variable VAR holding the passphrase the device server "
                    "seals its link with (its name, never the passphrase)");
    return {demo_mesh, demo_resolution};
}

// Haptics, persistence, the tool's operation, the compute paths and the elastic press.
void declare_session_options(CLI::App& cmd, DemoCli& o, std::pair<CLI::Option*, CLI::Option*> workpiece_excludes) {
    auto [demo_mesh, demo_resolution] = workpiece_excludes;
    cmd.add_option("--workspace", o.demo.workspace, "Workspace technique: peng_moving, scaling, clutching or bubble")
        ->capture_default_str();
    cmd.add_option("--static-friction", o.demo.static_friction, "Coulomb static friction coefficient")->capture_default_str();
    cmd.add_option("--dynamic-friction", o.demo.dynamic_friction, "Coulomb dynamic friction coefficient")->capture_default_str();
    cmd.add_flag("--no-cutting-force", o.no_cutting, "No reaction force against the tool's advance while carving");
    cmd.add_option("--record", o.demo.record, "Record the session to FILE (TRDXREC, thesis Table 3 fields)");
    cmd.add_option("--save", o.demo.save, "Save the final model to FILE.tdx (tri-dexel model file)");
    cmd.add_option("--workpiece", o.demo.workpiece,
                         "Start from a saved model FILE.tdx (from --save) instead of a mesh; it decides the resolution")
        ->check(CLI::ExistingFile)
        ->excludes(demo_mesh)
        ->excludes(demo_resolution);
    auto* demo_journal = cmd.add_option("--journal", o.demo.journal,
                                              "Session journal FILE (default: OUT/session.tdj; `tridex recover FILE` rebuilds the model)");
    cmd.add_flag("--no-journal", o.demo.no_journal, "Write no session journal")->excludes(demo_journal);
    cmd.add_option("--checkpoint-s", o.demo.checkpoint_s,
                         "Seconds between checkpoint models written next to the journal while sculpting (0 = none)")
        ->capture_default_str();
    cmd.add_option("--history-mib", o.demo.history_mib, "Memory for undo, MiB (oldest strokes dropped first)")
        ->capture_default_str();
    cmd.add_flag("--keep-islands", o.demo.keep_islands, kKeepIslandsHelp);
    cmd
        .add_option("--op", o.demo.op,
                     "What the tool does: subtract, union (add material), paint, push, smooth, pull, grab (clay: move material) "
                     "or place (the whole workpiece follows the tool; nothing carved)")
        ->capture_default_str();
    cmd.add_option("--symmetry", o.demo.symmetry,
                   std::string("Sculpting symmetry about the workpiece's centre: ") + symmetry_forms() +
                       " (mirror planes through the centre, or N copies about an axis)")
        ->capture_default_str();
    cmd.add_option("--material", o.demo.material, "Palette id 1..7 that union adds and paint sets")->capture_default_str();
    auto* demo_cpu = cmd.add_flag("--cpu", o.demo.cpu, "Sculpt on the CPU pool whatever the Vulkan device (default: by the device's type: the CPU pool on a CPU implementation such as lavapipe, the GPU compute path on a GPU)");
    cmd.add_flag("--gpu", o.demo.gpu, "Sculpt on the GPU compute path (Vulkan) whatever the device's type, lavapipe included")->excludes(demo_cpu);
    auto* demo_cpu_contour = cmd.add_flag("--cpu-contour", o.demo.cpu_contour,
                       "Contour on the CPU even when sculpting on the GPU (default: GPU contouring, drawn with indirect "
                       "draws, on a real GPU; CPU contouring on a CPU Vulkan such as lavapipe)");
    cmd.add_flag("--gpu-contour", o.demo.gpu_contour,
                       "Contour on the GPU even on a CPU Vulkan implementation (lavapipe), where it is slower; it reads "
                       "the model on the GPU, so there it also sculpts on the GPU compute path")
        ->excludes(demo_cpu_contour)
        ->excludes(demo_cpu);
    cmd.add_flag("--gpu-clay", o.demo.gpu_clay,
                       "Push, smooth, pull and grab on the GPU clay kernel even on a CPU Vulkan implementation (lavapipe), "
                       "where the CPU reference is faster (same result bit for bit); there it also sculpts on the GPU "
                       "compute path")
        ->excludes(demo_cpu);

    cmd.add_flag("--elastic", o.elastic,
                       "Press an elastic object (a squeeze ball) in steps and let go: its drawn surface dents within the "
                       "radius of influence and springs back; the force comes from the undeformed surface");
    cmd.add_option("--scene", o.elastic_scene,
                         "--elastic: the scene file (objects, tool, press); default: assets/squeeze_ball_scene.json")
        ->check(CLI::ExistingFile);
}

// --elastic runs the elastic press; the scene file sets everything but the outputs.
int run_elastic(const CLI::App& cmd, const DemoCli& o) {
    if (!o.elastic) throw Error("--scene: only with --elastic");
    for (const CLI::Option* opt : cmd.get_options()) {
        const std::string name = opt->get_name();
        if (opt->count() > 0 && name != "--elastic" && name != "--scene" && name != "--out" && name != "--width" &&
            name != "--height" && name != "--validate" && name != "--help")
            throw Error("--elastic: " + name + " does not apply (the scene file sets the objects, the tool and the press)");
    }
    ElasticDemoOptions elastic;
    elastic.scene = o.elastic_scene;
    if (cmd.count("--out") > 0) elastic.out = o.demo.out;
    elastic.width = o.demo.width;
    elastic.height = o.demo.height;
    elastic.validate = o.demo.validate;
    run_elastic_demo(elastic);
    return 0;
}

CommandAction setup_demo(CLI::App& cmd) {
    auto o = std::make_shared<DemoCli>();
    declare_session_options(cmd, *o, declare_workpiece_tool_device(cmd, *o));
    return [o, &cmd]() -> int {
        if (o->elastic || cmd.count("--scene") > 0) return run_elastic(cmd, *o);
        DemoOptions demo = o->demo;
        // Options that only one tool reads are refused with the others rather than ignored.
        if (cmd.count("--tool-length-mm") > 0 && demo.tool != "flat_end")
            throw Error("--tool-length-mm: only with --tool flat_end");
        demo.tool_radius_m = o->tool_radius_mm * 1e-3;
        demo.tool_length_m = o->tool_length_mm * 1e-3;
        demo.tool_size_m = o->tool_size_mm * 1e-3;
        demo.cutting = !o->no_cutting;
        demo.ao = o->ao == "on";
        run_demo(demo);
        return 0;
    };
}

const CommandRegistration kRegistration{
    {"demo", "Carve the workpiece with a scripted stroke under the 1 kHz haptic loop and write stereo frames", 10,
     setup_demo}};

}  // namespace
}  // namespace tridex::app
