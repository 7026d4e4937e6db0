// app/commands/devices/devices_command.cpp - `tridex devices`: the drivers and the hardware that is plugged in.
#include <CLI/CLI.hpp>

#include <memory>

#include "app/commands/command.hpp"
#include "app/commands/devices/devices.hpp"

namespace tridex::app {
namespace {

CommandAction setup_devices(CLI::App& cmd) {
    auto json = std::make_shared<bool>(false);
    cmd.add_flag("--json", *json, "Print a JSON list of objects (name, driver, dof, capabilities, detected, ...)");
    return [json] {
        run_devices(*json);
        return 0;
    };
}

const CommandRegistration kRegistration{
    {"devices", "List the haptic device drivers and the known hardware that is plugged in", 60, setup_devices}};

}  // namespace
}  // namespace tridex::app
