// app/commands/run/run_command.cpp - `tridex run [SCENE]`: a stereo session in a window, fullscreen or offscreen.
#include <CLI/CLI.hpp>

#include <memory>

#include "app/commands/command.hpp"
#include "app/commands/run/run_cli.hpp"

namespace tridex::app {
namespace {

CommandAction setup_run(CLI::App& cmd) {
    auto o = std::make_shared<RunOptions>();
    add_run_options(cmd, *o);
    return [o] { return run_command(*o); };
}

const CommandRegistration kRegistration{
    {"run", "A stereo session: haptic loop + sculpt thread + rendering in a window, fullscreen or offscreen", 20,
     setup_run}};

}  // namespace
}  // namespace tridex::app
