// app/commands/devices/devices.hpp - `tridex devices`: the drivers this build has and the known hardware plugged in.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "devices/registry/device_registry.hpp"

namespace tridex::app {

/// One row per device a session can use or that was seen: each profile of each software driver (simulated,
/// replay) and each known hardware product, as objects {`name` (product), `driver`, `profile` (software
/// drivers), `dof` (actuated DOF, the usual "3-DOF force" count), `dof_in`, `dof_out`, `hardware`,
/// `available` (this build can drive it), `detected` (software: always true; hardware: plugged in now),
/// `usb_ids` ["vvvv:pppp"], `locations` (where each detected unit is), `summary`}. `usb_error` (may be null)
/// gets why USB could not be listed.
nlohmann::json devices_json(const devices::DeviceRegistry& registry, std::string* usb_error = nullptr);

/// The same rows as a table for a person, followed by a line on USB detection.
std::string devices_text(const nlohmann::json& rows, const std::string& usb_error);

/// `tridex devices [--json]`: prints devices_text or the JSON list (one document) of builtin_registry().
void run_devices(bool json);

}  // namespace tridex::app
