// app/actions/bindings.hpp - device buttons and axes bound to actions, as a VR lab's configuration binds a wand's
// buttons to tools: defaults from each driver's capabilities, overridden by a bindings file (docs/formats/bindings.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "devices/driver_capabilities.hpp"

namespace tridex::app {

/// One device's bindings: its buttons (bit, name, action) and what its joystick's y axis drives.
struct DeviceBindings {
    std::string device;                     ///< what the messages call it: "the flystick driver", "the wand"
    std::vector<devices::ButtonInfo> buttons;  ///< every button the device has; default_action is the bound action
    std::string joystick_y;                 ///< an axis action ("nav.scale", "tool.scale"), "" = none
    bool has_joystick = false;              ///< the device has a joystick to bind
    int engage_bit = -1;                    ///< the one bit "engage" may be bound to (the driver's), -1: none
    int workspace_bit = -1;                 ///< the one bit "workspace" may be bound to (the driver's), -1: none
    /// The action bound to bit `bit`, or "".
    const std::string& action_of(int bit) const;
};

/// The session's bindings: the tool device's and the wand's.
struct Bindings {
    DeviceBindings tool;  ///< the haptic device or tracked tool (DeviceState::buttons)
    DeviceBindings wand;  ///< the navigation wand (a DTrack Flystick: WandSample::buttons, joystick_y)
    std::string source = "the drivers' defaults";  ///< where they came from: "the drivers' defaults" or the file
};

/// The Flystick buttons a wand binds: bit 0 "trigger", bits 1..7 "button1".."button7" (DTrack's `6df2` numbering).
std::vector<devices::ButtonInfo> flystick_wand_buttons();

/// Defaults: the tool's buttons as its driver declares them (DriverCapabilities::buttons, with their default
/// actions) and the wand's: trigger nav.grab, button1 menu, button2 view.reset, joystick y nav.scale.
Bindings default_bindings(const std::string& driver_name, const devices::DriverCapabilities& tool_caps);

/// Applies a bindings object over `b`: {"tool": {"buttons": {NAME: ACTION, ...}}, "wand": {"buttons": {...},
/// "joystick_y": ACTION}}, ACTION an action name of builtin_actions() or "none". `where` names the file for errors.
/// Throws tridex::Error "WHERE: bindings.tool.buttons.NAME: ..." for an unknown device section or key, a button the
/// device lacks (listing the ones it has), an unknown action (with the nearest name), an axis action on a button or a
/// command on an axis, "engage" or "workspace" on another button than the driver's own, "nav.grab" on the tool, or a
/// value that is not a string.
void apply_bindings(const nlohmann::json& bindings, const std::string& where, Bindings& b);

/// Reads a bindings file (a JSON object whose "bindings" member is as apply_bindings takes it) over the defaults.
/// Throws tridex::Error naming the file (and line and column for malformed JSON) or the field.
Bindings load_bindings(const std::string& path, const std::string& driver_name,
                       const devices::DriverCapabilities& tool_caps);

/// The bindings as report.json and `tridex devices` show them: {"source", "tool": {NAME: ACTION}, "wand": {...}}.
nlohmann::json bindings_json(const Bindings& b);

/// Reads one device's buttons frame by frame: presses of buttons bound to commands, and which held actions are held.
class BindingReader {
public:
    explicit BindingReader(const DeviceBindings& bindings) : bindings_(bindings) {}
    /// The device's button bits now; appends the command actions whose button went down since the last call, in
    /// the order of the device's buttons. A button already held at the first call does nothing until it is released
    /// and pressed again.
    void update(std::uint64_t buttons, std::vector<std::string>& pressed);
    /// True while a button bound to `action` (a held action: "menu", "nav.grab") is held.
    bool held(const std::string& action) const;
    /// The bindings read.
    const DeviceBindings& bindings() const { return bindings_; }

private:
    DeviceBindings bindings_;
    std::uint64_t prev_ = 0;
    bool first_ = true;
};

}  // namespace tridex::app
