// app/actions/bindings.cpp - default bindings from the drivers' capabilities, a bindings file over them, and the
// per-frame reading of buttons into actions.
#include "app/actions/bindings.hpp"

#include <fstream>
#include <iterator>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/actions/action_registry.hpp"
#include "core/error.hpp"
#include "core/text/json_refusal.hpp"

namespace tridex::app {

namespace {

// The names of a device's buttons, for "its buttons: ..." in errors.
std::string button_names(const DeviceBindings& d) {
    std::string s;
    for (const devices::ButtonInfo& b : d.buttons) s += (s.empty() ? "" : ", ") + b.name;
    return s.empty() ? "none" : s;
}

// Checks that `action` may be bound to button `bit` of `d` (field names the place for errors).
void check_button_action(const DeviceBindings& d, int bit, const std::string& action, bool is_tool,
                         const std::string& field) {
    if (action.empty()) return;
    const Action& a = builtin_actions().get(action, field);
    if (a.kind == ActionKind::kAxis) throw Error(field + ": '" + action + "' is driven by an axis; bind it to joystick_y");
    if (action == "engage" && bit != d.engage_bit)
        throw Error(field + ": 'engage' goes on the button the loop reads to carve (" +
                    (d.engage_bit < 0 ? std::string("this device carves without one") : "bit " + std::to_string(d.engage_bit)) + ")");
    if (action == "workspace" && bit != d.workspace_bit)
        throw Error(field + ": 'workspace' goes on the stylus button the workspace techniques read (" +
                    (d.workspace_bit < 0 ? std::string("this device has none") : "bit " + std::to_string(d.workspace_bit)) + ")");
    if (action == "nav.grab" && is_tool) throw Error(field + ": 'nav.grab' is the wand's; the tool carves");
    if (!is_tool && (action == "engage" || action == "workspace"))
        throw Error(field + ": '" + action + "' is the tool device's; the wand navigates");
}

void apply_device(const nlohmann::json& j, const std::string& where, const std::string& prefix, bool is_tool,
                  DeviceBindings& d) {
    if (!j.is_object()) throw Error(where + ": " + prefix + ": must be an object {\"buttons\": {...}}");
    for (const auto& [key, value] : j.items()) {
        const std::string field = prefix + "." + key;
        if (key == "buttons") {
            if (!value.is_object()) throw Error(where + ": " + field + ": must be an object {NAME: ACTION}");
            for (const auto& [name, act] : value.items()) {
                const std::string bf = where + ": " + field + "." + name;
                if (!act.is_string()) throw Error(bf + ": must be an action name or \"none\"");
                devices::ButtonInfo* button = nullptr;
                for (devices::ButtonInfo& b : d.buttons)
                    if (b.name == name) button = &b;
                if (!button)
                    throw Error(bf + ": " + d.device + " has no button '" + name + "'; its buttons: " + button_names(d));
                const std::string action = act.get<std::string>() == "none" ? "" : act.get<std::string>();
                check_button_action(d, button->bit, action, is_tool, bf);
                button->default_action = action;
            }
        } else if (key == "joystick_y") {
            const std::string jf = where + ": " + field;
            if (!d.has_joystick) throw Error(jf + ": " + d.device + " has no joystick to bind");
            if (!value.is_string()) throw Error(jf + ": must be an action name or \"none\"");
            const std::string action = value.get<std::string>() == "none" ? "" : value.get<std::string>();
            if (!action.empty() && builtin_actions().get(action, jf).kind != ActionKind::kAxis)
                throw Error(jf + ": '" + action + "' is not driven by an axis; axes drive nav.scale or tool.scale");
            if (action == "nav.scale" && is_tool) throw Error(jf + ": 'nav.scale' is the wand's; the tool's joystick scales the tool");
            d.joystick_y = action;
        } else {
            throw Error(where + ": " + field + ": unknown field; use buttons" +
                        std::string(d.has_joystick ? " or joystick_y" : ""));
        }
    }
}

}  // namespace

const std::string& DeviceBindings::action_of(int bit) const {
    static const std::string none;
    for (const devices::ButtonInfo& b : buttons)
        if (b.bit == bit) return b.default_action;
    return none;
}

std::vector<devices::ButtonInfo> flystick_wand_buttons() {
    std::vector<devices::ButtonInfo> out{{0, "trigger", "nav.grab"}, {1, "button1", "menu"}, {2, "button2", "view.reset"}};
    for (int i = 3; i <= 7; ++i) out.push_back({i, "button" + std::to_string(i), ""});
    return out;
}

Bindings default_bindings(const std::string& driver_name, const devices::DriverCapabilities& caps) {
    Bindings b;
    b.tool.device = "the " + driver_name + " driver";
    b.tool.buttons = caps.buttons;
    b.tool.engage_bit = caps.engage_button;
    b.tool.workspace_bit = caps.workspace_button;
    b.tool.has_joystick = caps.joystick;
    if (caps.joystick) b.tool.joystick_y = "tool.scale";
    b.wand.device = "the wand (a Flystick)";
    b.wand.buttons = flystick_wand_buttons();
    b.wand.has_joystick = true;
    b.wand.joystick_y = "nav.scale";
    return b;
}

void apply_bindings(const nlohmann::json& j, const std::string& where, Bindings& b) {
    if (!j.is_object()) throw Error(where + ": bindings: must be an object {\"tool\": {...}, \"wand\": {...}}");
    for (const auto& [key, value] : j.items()) {
        // The two sections by name (a table, so that a section's name is never read as a driver's).
        static const std::string kSections[2] = {"tool", "wand"};
        if (key == kSections[0])
            apply_device(value, where, "bindings.tool", true, b.tool);
        else if (key == kSections[1])
            apply_device(value, where, "bindings.wand", false, b.wand);
        else
            throw Error(where + ": bindings." + key + ": unknown device; use tool or wand");
    }
    b.source = where;
}

Bindings load_bindings(const std::string& path, const std::string& driver_name,
                       const devices::DriverCapabilities& caps) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot read the bindings file");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {  // the line, column and what was expected; 1e400 and its field
        throw Error(path + ": not valid JSON: " + json_refusal<nlohmann::json>(text, e));
    }
    if (!j.is_object() || !j.contains("bindings"))
        throw Error(path + ": bindings: missing; the file holds {\"bindings\": {\"tool\": {...}, \"wand\": {...}}}");
    for (const auto& [key, value] : j.items())
        if (key != "bindings" && key != "comment") throw Error(path + ": " + key + ": unknown field; use bindings");
    Bindings b = default_bindings(driver_name, caps);
    apply_bindings(j.at("bindings"), path, b);
    return b;
}

nlohmann::json bindings_json(const Bindings& b) {
    const auto device = [](const DeviceBindings& d) {
        nlohmann::json buttons = nlohmann::json::object();
        for (const devices::ButtonInfo& x : d.buttons)
            if (!x.default_action.empty()) buttons[x.name] = x.default_action;
        nlohmann::json o{{"buttons", buttons}};
        if (d.has_joystick) o["joystick_y"] = d.joystick_y.empty() ? "none" : d.joystick_y;
        return o;
    };
    return {{"source", b.source}, {"tool", device(b.tool)}, {"wand", device(b.wand)}};
}

void BindingReader::update(std::uint64_t buttons, std::vector<std::string>& pressed) {
    const std::uint64_t went_down = first_ ? 0 : buttons & ~prev_;
    // A button held from the start counts once released and pressed again.
    prev_ = buttons;
    first_ = false;
    for (const devices::ButtonInfo& b : bindings_.buttons) {
        if (b.bit < 0 || b.bit > 63 || b.default_action.empty()) continue;
        if ((went_down >> b.bit) & 1u) {
            const Action* a = builtin_actions().find(b.default_action);
            if (a && a->kind == ActionKind::kCommand) pressed.push_back(b.default_action);
        }
    }
}

bool BindingReader::held(const std::string& action) const {
    for (const devices::ButtonInfo& b : bindings_.buttons)
        if (b.default_action == action && b.bit >= 0 && b.bit <= 63 && ((prev_ >> b.bit) & 1u)) return true;
    return false;
}

}  // namespace tridex::app
