// devices/device_registry.cpp - the registry, the built-in drivers and USB detection.
#include "devices/device_registry.hpp"

#include <libusb-1.0/libusb.h>

#include <algorithm>
#include <cstdlib>
#include <cstdio>
#include <utility>

#include "core/error.hpp"
#include "devices/device_profiles.hpp"
#include "devices/falcon/falcon_device.hpp"
#include "devices/falcon/falcon_emulator.hpp"
#include "devices/falcon/falcon_firmware.hpp"
#include "devices/falcon/falcon_usb_transport.hpp"
#include "devices/net/enet_link.hpp"
#include "devices/net/net_device.hpp"
#include "devices/mouse_device.hpp"
#include "devices/replay_device.hpp"
#include "devices/simulated_device.hpp"
#include "devices/spacemouse_device.hpp"
#include "devices/tracking/tracked_tool_device.hpp"

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

const DeviceRegistry& builtin_registry() {
    static const DeviceRegistry registry = [] {
        DeviceRegistry r;
        DriverInfo sim{"simulated",
                       "closed-loop virtual hand on a simulated device (profiles: omni = PHANTOM Omni, wand = Quanser "
                       "5-DOF wand, 6dof = generic 6-DOF, falcon = Novint Falcon)",
                       false,
                       true,
                       {"omni", "wand", "6dof", "falcon"},
                       {},
                       6,
                       3};
        r.add(sim, [](const DeviceSpec& spec, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
            DeviceProfile profile = profile_by_name(spec.profile);
            ScriptedPath path = in.hand_path ? *in.hand_path : ScriptedPath::hold(Vec3(0.0));
            auto dev = std::make_unique<SimulatedDevice>(std::move(profile), std::move(path), SimulatedHandParams{},
                                                         in.period_s);
            if (in.buttons) dev->set_button_script(*in.buttons);
            return dev;
        });
        DriverInfo replay{"replay",
                          "plays a recording's device samples back (tridex replay)",
                          false,
                          true,
                          {"omni", "wand", "6dof", "falcon"},
                          {},
                          6,
                          3};
        r.add(replay, [](const DeviceSpec& spec, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
            return std::make_unique<ReplayDevice>(profile_by_name(spec.profile), in.samples);
        });
        // The Novint Falcon: FTDI vendor 0x0403, Novint product 0xcb48 (libnifalcon's udev rules), over libusb-1.0.
        DriverInfo falcon{"falcon", "Novint Falcon (3-DOF force, USB)",        true, true,
                          {},       {{falcon::kVendorId, falcon::kProductId}}, 3,    3};
        r.add(falcon, [](const DeviceSpec& spec, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
            bool plugged = false;
            for (const auto& [id, where] : usb_devices())
                plugged = plugged || (id.vendor == falcon::kVendorId && id.product == falcon::kProductId &&
                                      (spec.serial.empty() || where == spec.serial));
            if (!plugged)
                throw Error("device.driver: no Novint Falcon is plugged in (USB 0403:cb48" +
                            (spec.serial.empty() ? std::string() : " at " + spec.serial) +
                            "); `tridex devices` lists what is; --device falcon-emulator runs without one");
            falcon::FalconDeviceOptions o;
            o.firmware_path = in.falcon_firmware;
            o.period_s = in.period_s;
            return std::make_unique<falcon::FalconDevice>(std::make_unique<falcon::FalconUsbTransport>(spec.serial), o);
        });
        DriverInfo emulator{
            "falcon-emulator",
            "the Falcon driver over an emulated Falcon (protocol, firmware load, homing), its grip held by "
            "the simulated hand",
            false,
            true,
            {"falcon"},
            {},
            3,
            3};
        r.add(emulator, [](const DeviceSpec&, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
            falcon::FalconEmulatorConfig c;
            c.hand_path = in.hand_path;
            c.buttons = in.buttons;
            c.period_s = in.period_s;
            falcon::FalconDeviceOptions o;
            o.firmware_image = falcon::emulator_firmware_image();  // generated; never a vendor binary
            o.period_s = in.period_s;
            return std::make_unique<falcon::FalconDevice>(std::make_unique<falcon::FalconEmulator>(std::move(c)), o);
        });
        DriverInfo netinfo{"net",
                           "a device on another machine served by `tridex device-server` (--device net:HOST:PORT; "
                           "--haptic-rendering distributed or local)",
                           false, true, {}, {}, 6, 3};
        r.add(netinfo, [](const DeviceSpec& spec, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
            std::string host;
            std::uint16_t port = 0;
            net::split_host_port(spec.serial, "--device net:HOST:PORT", host, port);
            net::NetDeviceOptions o;
            o.mode = net::rendering_mode_from(in.haptic_rendering);
            o.period_s = in.period_s;
            auto dev = std::make_unique<net::NetDevice>(net::EnetLink::connect(host, port), o);
            dev->wait_for_server(3.0);
            return dev;
        });
        DriverInfo mouse{"mouse",
                         "the desk mouse as a virtual stylus: the app sets the hand from the cursor (no forces; the "
                         "profile's limits still bound what the loop sends)",
                         false, true, {"omni", "wand", "6dof"}, {}, 3, 3};
        r.add(mouse, [](const DeviceSpec& spec, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
            DeviceProfile profile = profile_by_name(spec.profile);
            profile.name = "mouse (" + profile.name + " limits)";
            const Vec3 start = in.hand_path ? in.hand_path->position_at(0.0) : Vec3(0.0);
            return std::make_unique<MouseDevice>(std::move(profile), start, in.period_s);
        });
        // A 6-DOF 3D mouse through spacenavd's socket: spec.serial, else $SPNAV_SOCKET (as libspnav), else the default.
        DriverInfo spacemouse{"spacemouse",
                              "a 6-DOF 3D mouse through spacenavd (rate control of the stylus pose; no forces)",
                              false, true, {"omni", "wand", "6dof"}, {}, 6, 0};  // no USB ids: spacenavd finds it
        r.add(spacemouse, [](const DeviceSpec& spec, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
            DeviceProfile profile = profile_by_name(spec.profile);
            profile.name = "spacemouse (" + profile.name + " limits)";
            SpaceMouseParams p = in.spacemouse.value_or(SpaceMouseParams{});
            const char* env = std::getenv("SPNAV_SOCKET");
            p.socket_path = !spec.serial.empty() ? spec.serial : (env && *env) ? env : kSpnavDefaultSocket;
            const Vec3 start = in.hand_path ? in.hand_path->position_at(0.0) : Vec3(0.0);
            return std::make_unique<SpaceMouseDevice>(std::move(profile), start, in.period_s, std::move(p));
        });
        // A DTrack-tracked Flystick or standard body as the tool (no haptic device): the session's receiver
        // (shared with the head or the wand on the same port), else one of its own.
        for (const bool flystick : {true, false}) {
            DriverInfo info{flystick ? "flystick" : "tracked-body",
                            flystick ? "an ART DTrack Flystick as the tool (6df2; its trigger engages the tool; no forces)"
                                     : "an ART DTrack standard body as the tool (6d; always engaged; no forces)",
                            false, true, {"tracked"}, {}, 6, 0};
            r.add(info, [flystick](const DeviceSpec&, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
                TrackedToolParams p = in.tracked_tool;
                p.flystick = flystick;
                std::shared_ptr<DTrackReceiver> rx =
                    in.dtrack ? in.dtrack : std::make_shared<DTrackReceiver>(in.dtrack_port, in.dtrack_bind);
                return std::make_unique<TrackedToolDevice>(tracked_tool_profile(), std::move(rx), p, in.period_s);
            });
        }
        return r;
    }();
    return registry;
}

std::string usb_id_string(const UsbId& id) { return hex4(id.vendor) + ":" + hex4(id.product); }

}  // namespace tridex::devices
