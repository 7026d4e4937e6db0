// app/commands/replay_command.cpp - `tridex replay FILE`: sculpt a recorded session again.
#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "app/commands/command.hpp"
#include "app/commands/replay.hpp"

namespace tridex::app {
namespace {

struct ReplayCli {
    std::string file;
    OutputOptions out;
    SculptOptions sculpt;
    std::string save;
    bool keep_islands = false;
};

CommandAction setup_replay(CLI::App& cmd) {
    auto o = std::make_shared<ReplayCli>();
    o->out.out = "out/replay";
    cmd.add_option("FILE", o->file, "Recording made with `tridex demo --record FILE`")->required()->check(CLI::ExistingFile);
    cmd.add_option("--out", o->out.out, "Output folder")->capture_default_str();
    cmd.add_option("--width", o->out.width, "Per-eye image width, px")->capture_default_str();
    cmd.add_option("--height", o->out.height, "Per-eye image height, px")->capture_default_str();
    cmd.add_flag("--validate", o->out.validate, "Enable the Vulkan validation layer");
    cmd.add_flag("--cpu", o->sculpt.cpu, "Sculpt on the CPU reference instead of the GPU (Vulkan compute)");
    auto* cpu_contour =
        cmd.add_flag("--cpu-contour", o->sculpt.cpu_contour, "Contour on the CPU even when sculpting on the GPU (as for demo)");
    cmd.add_flag("--gpu-contour", o->sculpt.gpu_contour,
                 "Contour on the GPU even on a CPU Vulkan implementation (lavapipe), where it is slower")
        ->excludes(cpu_contour);
    cmd.add_flag("--gpu-clay", o->sculpt.gpu_clay,
                 "Push, smooth and pull on the GPU clay kernel even on a CPU Vulkan implementation (lavapipe)");
    cmd.add_option("--save", o->save, "Save the final model to FILE.tdx (as `tridex demo --save`)");
    cmd.add_flag("--keep-islands", o->keep_islands,
                 "Keep the specks cuts left floating even when the recorded session removed them (default: as the "
                 "recording says)");
    return [o] {
        run_replay(o->file, o->out, o->sculpt, o->save, o->keep_islands);
        return 0;
    };
}

const CommandRegistration kRegistration{
    {"replay", "Sculpt a recorded session again and write the demo's outputs", 30, setup_replay}};

}  // namespace
}  // namespace tridex::app
