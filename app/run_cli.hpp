// app/run_cli.hpp - the `tridex run` subcommand (main.cpp adds it with two lines).
#pragma once

#include "app/run_options.hpp"

namespace CLI {
class App;
}

namespace tridex::app {

/// Adds `run [SCENE] --display window|fullscreen|offscreen --stereo MODE [--monitor N|NAME] [--frames N]
/// [--out DIR] [--display-config FILE] [--head fixed|scripted|tracker] [--swap-eyes] [--seconds S] [--validate]
/// [--no-pace]` to `cli`, parsing into `options` (which must outlive the parse). Returns the subcommand, so the
/// caller can test `if (*cmd)` after parsing.
CLI::App* add_run_command(CLI::App& cli, RunOptions& options);

/// Runs the session (run_stereo_session) and prints a short summary on stdout. Returns 0 on success, 2 after
/// printing "tridex: <message>" to stderr for a tridex::Error (a bad option, scene or display config field, an
/// output the display cannot show, no Vulkan device or display), 3 when out of memory, 4 when the device was lost
/// during the session (after its outputs were written; the message names the device, when, and what was kept).
int run_command(const RunOptions& options);

}  // namespace tridex::app
