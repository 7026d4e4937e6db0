// app/commands/replay/replay_command.cpp - `tridex replay FILE`: sculpt a recorded session again.
#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <tuple>

#include "app/commands/command.hpp"
#include "app/commands/replay/replay.hpp"

namespace tridex::app {
namespace {

struct ReplayCli {
    std::string file;
    OutputOptions out;
    SculptOptions sculpt;
    std::string save;
    StripRequest strip;
    std::string strip_size = "320x240";
    bool keep_islands = false;
    bool realtime = false;
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
                 "Push, smooth, pull and grab on the GPU clay kernel even on a CPU Vulkan implementation (lavapipe); there "
                 "it also sculpts on the GPU compute path")
        ->excludes(cpu);
    cmd.add_option("--save", o->save, "Save the final model to FILE.tdx (as `tridex demo --save`)");
    cmd.add_flag("--keep-islands", o->keep_islands,
                 "Keep the specks cuts left floating even when the recorded session removed them (default: as the "
                 "recording says)");
    cmd.add_flag("--realtime", o->realtime,
                 "Play the samples at the recorded rate, taking as long as the session did (default: as fast as the "
                 "sculpting goes; the same model either way)");
    cmd.add_option(
        "--strip", o->strip.path,
        "Also draw the carve as a film strip: pictures of the model spread over the stretch where it changed, "
        "side by side, into FILE.png");
    cmd.add_option("--strip-frames", o->strip.options.frames, "Pictures in the film strip, 2..24")->capture_default_str();
    cmd.add_option("--strip-size", o->strip_size, "Each picture's size in the film strip, WxH px")->capture_default_str();
    return [o] {
        std::tie(o->strip.options.width, o->strip.options.height) = parse_image_size(o->strip_size, "--strip-size");
        o->strip.options.ao = o->out.ao;
        run_replay(o->file, o->out, o->sculpt, o->save, o->strip, o->keep_islands, o->realtime);
        return 0;
    };
}

const CommandRegistration kRegistration{
    {"replay", "Sculpt a recorded session again and write the demo's outputs", 30, setup_replay}};

}  // namespace
}  // namespace tridex::app
