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
};

CommandAction setup_replay(CLI::App& cmd) {
    auto o = std::make_shared<ReplayCli>();
    o->out.out = "out/replay";
    cmd.add_option("FILE", o->file, "Recording made with `tridex demo --record FILE`")->required()->check(CLI::ExistingFile);
    cmd.add_option("--out", o->out.out, "Output folder")->capture_default_str();
    cmd.add_option("--width", o->out.width, "Per-eye image width, px")->capture_default_str();
    cmd.add_option("--height", o->out.height, "Per-eye image height, px")->capture_default_str();
    cmd.add_flag("--validate", o->out.validate, "Enable the Vulkan validation layer");
    auto* cpu = cmd.add_flag("--cpu", o->sculpt.cpu, "Sculpt on the CPU pool whatever the Vulkan device (default: by the device's type: the CPU pool on a CPU implementation such as lavapipe, the GPU compute path on a GPU)");
    cmd.add_flag("--gpu", o->sculpt.gpu, "Sculpt on the GPU compute path (Vulkan) whatever the device's type, lavapipe included")->excludes(cpu);
    auto* cpu_contour =
        cmd.add_flag("--cpu-contour", o->sculpt.cpu_contour, "Contour on the CPU even when sculpting on the GPU (as for demo)");
    cmd.add_flag("--gpu-contour", o->sculpt.gpu_contour,
                 "Contour on the GPU even on a CPU Vulkan implementation (lavapipe), where it is slower; it reads the "
                 "model on the GPU, so there it also sculpts on the GPU compute path")
        ->excludes(cpu_contour)
        ->excludes(cpu);
    cmd.add_flag("--gpu-clay", o->sculpt.gpu_clay,
                 "Push, smooth and pull on the GPU clay kernel even on a CPU Vulkan implementation (lavapipe); there "
                 "it also sculpts on the GPU compute path")
        ->excludes(cpu);
    cmd.add_option("--save", o->save, "Save the final model to FILE.tdx (as `tridex demo --save`)");
    return [o] {
        run_replay(o->file, o->out, o->sculpt, o->save);
        return 0;
    };
}

const CommandRegistration kRegistration{
    {"replay", "Sculpt a recorded session again and write the demo's outputs", 30, setup_replay}};

}  // namespace
}  // namespace tridex::app
