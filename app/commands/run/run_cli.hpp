// app/commands/run/run_cli.hpp - the `tridex run` subcommand (app/commands/run/run_command.cpp registers it).
#pragma once

#include <string>

#include "app/session/run/run_options.hpp"

namespace CLI {
class App;
}

namespace tridex::app {

/// Declares `run [SCENE] --display window|fullscreen|offscreen --stereo MODE [--monitor N|NAME] [--frames N]
/// [--out DIR] [--display-config FILE] [--head fixed|scripted|tracker] [--swap-eyes] [--seconds S] [--validate]
/// [--no-pace] ...` to the `run` subcommand `cmd`, parsing into `options` (which must outlive the parse).
void add_run_options(CLI::App& cmd, RunOptions& options);

/// The help of `run --device`, from the device registry: every driver a session can use with its summary, and
/// the simulated hand's profiles.
std::string device_option_help();

/// Runs the session (run_stereo_session) and prints a short summary on stdout. Returns 0 on success, 2 after
/// printing "tridex: <message>" to stderr for a tridex::Error (a bad option, scene or display config field, an
/// output the display cannot show, no Vulkan device or display), 3 when out of memory, 4 when the device was lost
/// during the session (after its outputs were written; the message names the device, when, and what was kept).
int run_command(const RunOptions& options);

}  // namespace tridex::app
