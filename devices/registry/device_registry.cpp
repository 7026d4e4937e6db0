// devices/registry/device_registry.cpp - the registry, choosing a driver from a command line, and USB detection.
#include "devices/registry/device_registry.hpp"

#include <libusb-1.0/libusb.h>

#include <algorithm>
#include <cstdlib>
#include <cstdio>
#include <utility>

#include "core/error.hpp"
#include "devices/device_profiles.hpp"

namespace tridex::devices {

namespace {

struct NamedProfile {
    const char* name;
    DeviceProfile (*make)();
};
const NamedProfile kProfiles[] = {{"omni", &DeviceProfile::phantom_omni},
                                  {"wand", &quanser_wand_5dof},
                                  {"6dof", &generic_6dof},
                                  {"falcon", &novint_falcon},
                                  {"tracked", &tracked_tool_profile}};

std::string join(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

std::string hex4(std::uint16_t v) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "%04x", v);
    return buf;
}

}  // namespace

std::string join_or(const std::vector<std::string>& names) {
    std::string out;
    for (std::size_t i = 0; i < names.size(); ++i)
        out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    return out;
}

DeviceProfile profile_by_name(const std::string& name) {
    for (const NamedProfile& p : kProfiles)
        if (name == p.name) return p.make();
    throw Error("device.profile: unknown profile '" + name + "'; use omni, wand, 6dof, falcon or tracked");
}

std::string profile_name_of(const std::string& product) {
    for (const NamedProfile& p : kProfiles)
        if (p.make().name == product) return p.name;
    return "";
}

std::vector<std::pair<UsbId, std::string>> usb_devices(std::string* error) {
    std::vector<std::pair<UsbId, std::string>> out;
    libusb_context* ctx = nullptr;
    if (const int rc = libusb_init(&ctx); rc != 0) {
        if (error) *error = std::string("libusb_init: ") + libusb_strerror(rc);
        return out;
    }
    libusb_device** list = nullptr;
    const ssize_t n = libusb_get_device_list(ctx, &list);
    if (n < 0) {
        if (error) *error = std::string("libusb_get_device_list: ") + libusb_strerror(static_cast<int>(n));
    } else {
        for (ssize_t i = 0; i < n; ++i) {
            libusb_device_descriptor d{};
            if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
            std::string where = "bus " + std::to_string(libusb_get_bus_number(list[i])) + " port ";
            std::uint8_t ports[8];
            const int depth = libusb_get_port_numbers(list[i], ports, 8);
            for (int k = 0; k < depth; ++k) where += (k ? "." : "") + std::to_string(ports[k]);
            if (depth <= 0) where += "root";
            out.push_back({UsbId{d.idVendor, d.idProduct}, where});
        }
        libusb_free_device_list(list, 1);
    }
    libusb_exit(ctx);
    return out;
}

void DeviceRegistry::add(DriverInfo info, Factory factory) {
    if (info.name.empty()) throw Error("DeviceRegistry::add: a driver needs a name");
    for (const Entry& e : entries_)
        if (e.info.name == info.name) throw Error("DeviceRegistry::add: driver '" + info.name + "' is registered twice");
    entries_.push_back({std::move(info), std::move(factory)});
}

std::unique_ptr<HapticDevice> DeviceRegistry::create(const DeviceSpec& spec, const DeviceInputs& inputs) const {
    std::vector<std::string> names;
    for (const Entry& e : entries_) {
        if (e.info.name == spec.driver) {
            if (!e.info.available || !e.factory)
                throw Error("device.driver: the '" + spec.driver + "' driver (" + e.info.summary +
                            ") is not available in this build");
            return e.factory(spec, inputs);
        }
        if (e.info.available) names.push_back(e.info.name);
    }
    throw Error("device.driver: unknown driver '" + spec.driver + "'; drivers: " + join(names));
}

std::vector<DriverInfo> DeviceRegistry::drivers() const {
    std::vector<DriverInfo> out;
    for (const Entry& e : entries_) out.push_back(e.info);
    return out;
}

const DriverInfo* DeviceRegistry::find(const std::string& name) const {
    for (const Entry& e : entries_)
        if (e.info.name == name) return &e.info;
    return nullptr;
}

const DriverInfo& DeviceRegistry::info(const std::string& name, const std::string& field) const {
    if (const DriverInfo* d = find(name)) return *d;
    std::vector<std::string> names;
    for (const Entry& e : entries_)
        if (e.info.available) names.push_back(e.info.name);
    throw Error(field + ": unknown driver '" + name + "'; drivers: " + join(names));
}

namespace {

// The default driver: the first scripted driver with profiles (the simulated hand), or null.
const DriverInfo* default_driver(const std::vector<DriverInfo>& all) {
    for (const DriverInfo& d : all)
        if (d.caps.input == InputKind::kScripted && !d.profiles.empty()) return &d;
    return nullptr;
}

bool accepts(const DeviceRegistry::DriverFilter& usable, const DriverInfo& d) {
    return d.available && d.caps.input != InputKind::kRecorded && (!usable || usable(d));
}

}  // namespace

std::vector<std::string> DeviceRegistry::choices(const DriverFilter& usable) const {
    const std::vector<DriverInfo> all = drivers();
    const DriverInfo* def = default_driver(all);
    std::vector<std::string> out;
    if (def && accepts(usable, *def))
        for (const std::string& p : def->profiles)
            if (!find(p)) out.push_back(p);
    for (const DriverInfo& d : all) {
        if (&d == def || !accepts(usable, d)) continue;
        const std::string& form = d.caps.address_form;
        out.push_back(form.empty() ? d.name : d.caps.address_required ? d.name + ":" + form : d.name + "[:" + form + "]");
    }
    return out;
}

DeviceChoice DeviceRegistry::choose(const std::string& text, const std::string& option, const DriverFilter& usable) const {
    const std::size_t colon = text.find(':');
    const std::string name = text.substr(0, colon);
    const std::string address = colon == std::string::npos ? std::string() : text.substr(colon + 1);
    const DriverInfo* d = find(name);
    if (d && accepts(usable, *d)) {
        if (colon != std::string::npos && d->caps.address_form.empty())
            throw Error(option + ": the '" + name + "' driver takes nothing after its name (\"" + text + "\")");
        if (address.empty() && d->caps.address_required)
            throw Error(option + ": " + name + ":" + d->caps.address_form + ", got '" + text + "'");
        return {d->name, d->caps.fixed_profile, address};
    }
    const std::vector<DriverInfo> all = drivers();
    const DriverInfo* def = default_driver(all);
    if (!d && def && accepts(usable, *def) && colon == std::string::npos)
        for (const std::string& p : def->profiles)
            if (p == text) return {def->name, p, ""};
    throw Error(option + ": unknown device '" + text + "'; use " + join_or(choices(usable)));
}

std::vector<DetectedDevice> DeviceRegistry::detect(std::string* error) const {
    std::vector<DetectedDevice> found;
    bool any_hardware = false;
    for (const Entry& e : entries_) any_hardware = any_hardware || !e.info.usb_ids.empty();
    if (!any_hardware) return found;
    for (const auto& [id, where] : usb_devices(error))
        for (const Entry& e : entries_)
            for (const UsbId& want : e.info.usb_ids)
                if (want.vendor == id.vendor && want.product == id.product)
                    found.push_back({e.info.name, e.info.summary, id, where});
    return found;
}

std::string_view to_string(InputKind kind) {
    switch (kind) {
        case InputKind::kScripted: return "scripted";
        case InputKind::kRecorded: return "recorded";
        case InputKind::kPointer: return "pointer";
        case InputKind::kRate: return "rate";
        case InputKind::kTracked: return "tracked";
        case InputKind::kHardware: return "hardware";
        case InputKind::kRemote: return "remote";
    }
    return "unknown";
}

std::string usb_id_string(const UsbId& id) { return hex4(id.vendor) + ":" + hex4(id.product); }

}  // namespace tridex::devices
