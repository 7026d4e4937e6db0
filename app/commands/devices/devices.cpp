// app/commands/devices/devices.cpp - `tridex devices`.
#include "app/commands/devices/devices.hpp"

#include <cstdio>
#include <tuple>
#include <utility>

namespace tridex::app {

namespace {

// What a driver says of itself (DriverCapabilities), as `tridex devices --json` prints it.
nlohmann::json capabilities_json(const devices::DriverCapabilities& c) {
    nlohmann::json options = nlohmann::json::array();
    for (const devices::DriverOption& o : c.options)
        options.push_back({{"name", o.name}, {"default", o.fallback}, {"min", o.min}, {"max", o.max},
                           {"min_exclusive", o.min_exclusive}, {"doc", o.doc}});
    nlohmann::json buttons = nlohmann::json::array();
    for (const devices::ButtonInfo& b : c.buttons)
        buttons.push_back({{"bit", b.bit}, {"name", b.name}, {"action", b.default_action.empty() ? "none" : b.default_action}});
    return {{"input", std::string(devices::to_string(c.input))},
            {"dof_in", c.dof_in},
            {"dof_out", c.dof_out},
            {"renders_forces", c.renders_forces},
            {"workspace_button", c.workspace_button},
            {"engage_button", c.engage_button},
            {"buttons", buttons},
            {"joystick", c.joystick},
            {"servable", c.servable},
            {"strokes_end_on_release", c.strokes_end_on_release},
            {"switches_op", c.switches_op},
            {"takes_firmware", c.takes_firmware},
            {"seals_link", c.seals_link},
            {"address", c.address_form},
            {"fixed_profile", c.fixed_profile},
            {"options", options}};
}

nlohmann::json usb_list(const std::vector<devices::UsbId>& ids) {
    nlohmann::json out = nlohmann::json::array();
    for (const devices::UsbId& id : ids) out.push_back(devices::usb_id_string(id));
    return out;
}

}  // namespace

nlohmann::json devices_json(const devices::DeviceRegistry& registry, std::string* usb_error) {
    const std::vector<devices::DetectedDevice> seen = registry.detect(usb_error);
    nlohmann::json rows = nlohmann::json::array();
    for (const devices::DriverInfo& d : registry.drivers()) {
        // A software driver's row per profile it takes (or one for a driver whose profile comes from elsewhere,
        // net: from its server).
        // One source of truth per row: a driver that renders forces has its profile's DOF; one that renders none (a
        // pointer, a 3D mouse, a tracker) senses its own DOF and outputs none, whatever profile bounds its loop.
        auto software_row = [&](const std::string& profile, const devices::DeviceProfile* p) {
            devices::DriverCapabilities caps = d.caps;
            if (!caps.renders_forces) caps.dof_out = 0;
            else if (p) std::tie(caps.dof_in, caps.dof_out) = std::pair(p->dof_in, p->dof_out);
            // An input-only driver's row is the driver under the profile's limits, not the profile's product.
            const std::string name = !p ? "(the served device's)" : d.caps.renders_forces ? p->name
                                                                   : d.name + " (" + p->name + " limits)";
            const std::string missing = d.detect_now ? d.detect_now() : "";
            nlohmann::json row = {{"name", name},
                                  {"driver", d.name},
                                  {"profile", profile},
                                  {"dof", caps.dof_out},
                                  {"dof_in", caps.dof_in},
                                  {"dof_out", caps.dof_out},
                                  {"hardware", false},
                                  {"available", d.available},
                                  {"detected", missing.empty()},
                                  {"usb_ids", nlohmann::json::array()},
                                  {"locations", nlohmann::json::array()},
                                  {"summary", d.summary},
                                  {"capabilities", capabilities_json(caps)}};
            if (!missing.empty()) row["not_detected"] = missing;
            rows.push_back(std::move(row));
        };
        if (!d.hardware && d.profiles.empty()) {
            software_row("-", nullptr);
            continue;
        }
        if (!d.hardware) {
            for (const std::string& name : d.profiles) {
                const devices::DeviceProfile p = devices::profile_by_name(name);
                software_row(name, &p);
            }
            continue;
        }
        nlohmann::json where = nlohmann::json::array();
        for (const devices::DetectedDevice& s : seen)
            if (s.driver == d.name) where.push_back(s.location + " (" + devices::usb_id_string(s.id) + ")");
        // A hardware driver is available only when this build has it and libusb finds a unit to drive.
        rows.push_back({{"name", d.summary},
                        {"driver", d.name},
                        {"dof", d.caps.dof_out},
                        {"dof_in", d.caps.dof_in},
                        {"dof_out", d.caps.dof_out},
                        {"hardware", true},
                        {"available", d.available && !where.empty()},
                        {"driver_in_build", d.available},
                        {"detected", !where.empty()},
                        {"usb_ids", usb_list(d.usb_ids)},
                        {"locations", where},
                        {"summary", d.summary},
                        {"capabilities", capabilities_json(d.caps)}});
    }
    return rows;
}

std::string devices_text(const nlohmann::json& rows, const std::string& usb_error) {
    std::string out = "Devices a session can use (scene: \"device\": {\"driver\": ..., \"profile\": ...}):\n";
    char line[512];
    for (const nlohmann::json& r : rows) {
        if (r["hardware"].get<bool>()) continue;
        // A driver that renders no force runs under the profile's limits only: say so rather than the profile's DOF.
        const bool forces = r["capabilities"]["renders_forces"].get<bool>();
        const std::string out_dof = forces ? std::to_string(r["dof_out"].get<int>()) + "-DOF force out" : "no force";
        std::snprintf(line, sizeof line, "  %-16s %-8s %-28s %-9s %d-DOF in, %s", r["driver"].get<std::string>().c_str(),
                      r["profile"].get<std::string>().c_str(), r["name"].get<std::string>().c_str(),
                      r["capabilities"]["input"].get<std::string>().c_str(), r["dof_in"].get<int>(), out_dof.c_str());
        out += line;
        out += r.contains("not_detected") ? "; not found now: " + r["not_detected"].get<std::string>() + "\n" : "\n";
    }
    out += "Hardware:\n";
    for (const nlohmann::json& r : rows) {
        if (!r["hardware"].get<bool>()) continue;
        std::string ids;
        for (const auto& id : r["usb_ids"]) ids += (ids.empty() ? "" : ", ") + id.get<std::string>();
        std::string state = r["detected"].get<bool>() ? "plugged in at " : "not plugged in";
        for (std::size_t i = 0; i < r["locations"].size(); ++i)
            state += (i ? ", " : "") + r["locations"][i].get<std::string>();
        const std::string driver = r.value("driver_in_build", false) ? "driver '" + r["driver"].get<std::string>() + "'"
                                                                     : "no driver in this build yet";
        std::snprintf(line, sizeof line, "  %-34s USB %s: %s; %s\n", r["name"].get<std::string>().c_str(), ids.c_str(),
                      state.c_str(), driver.c_str());
        out += line;
    }
    if (!usb_error.empty()) out += "  (USB devices could not be listed: " + usb_error + ")\n";
    return out;
}

void run_devices(bool json) {
    std::string usb_error;
    const nlohmann::json rows = devices_json(devices::builtin_registry(), &usb_error);
    const std::string text = json ? rows.dump(2) + "\n" : devices_text(rows, usb_error);
    std::fputs(text.c_str(), stdout);
}

}  // namespace tridex::app
