// devices/registry/builtin_drivers.cpp - the drivers this build has, each with what it says of itself.
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "devices/device_profiles.hpp"
#include "devices/registry/device_registry.hpp"
#include "devices/falcon/falcon_device.hpp"
#include "devices/falcon/falcon_emulator.hpp"
#include "devices/falcon/falcon_firmware.hpp"
#include "devices/falcon/falcon_usb_transport.hpp"
#include "devices/gamepad/gamepad_device.hpp"
#include "devices/mouse_device.hpp"
#include "devices/net/enet_link.hpp"
#include "devices/net/net_device.hpp"
#include "devices/net/sealed_link.hpp"
#include "devices/replay_device.hpp"
#include "devices/simulated_device.hpp"
#include "devices/spacemouse_device.hpp"
#include "devices/tracking/tracked_tool_device.hpp"

namespace tridex::devices {
namespace {

const std::vector<std::string> kHandProfiles = {"omni", "wand", "6dof"};

// The value of a driver option the scene set, else its fallback.
double option_or(const DeviceInputs& in, const std::string& name, double fallback) {
    const auto it = in.options.find(name);
    return it == in.options.end() ? fallback : it->second;
}

DriverInfo named(std::string name, std::string summary, bool hardware = false) {
    DriverInfo info;
    info.name = std::move(name);
    info.summary = std::move(summary);
    info.hardware = hardware;
    return info;
}

Vec3 start_of(const DeviceInputs& in) { return in.hand_path ? in.hand_path->position_at(0.0) : Vec3(0.0); }

void add_simulated(DeviceRegistry& r) {
    DriverInfo info = named("simulated",
                    "closed-loop virtual hand on a simulated device (profiles: omni = PHANTOM Omni, wand = Quanser "
                    "5-DOF wand, 6dof = generic 6-DOF, falcon = Novint Falcon)");
    info.profiles = {"omni", "wand", "6dof", "falcon"};
    info.caps.input = InputKind::kScripted;
    info.caps.dof_in = 6;
    info.caps.dof_out = 3;
    info.caps.renders_forces = true;
    info.caps.servable = true;
    // A stylus's two buttons (an Omni's): the first is the workspace button, the second opens the menu.
    info.caps.buttons = {{0, "button0", "workspace"}, {1, "button1", "menu"}, {2, "button2", "edit.undo"},
                         {3, "button3", "edit.redo"}};
    r.add(info, [](const DeviceSpec& spec, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
        DeviceProfile profile = profile_by_name(spec.profile);
        ScriptedPath path = in.hand_path ? *in.hand_path : ScriptedPath::hold(Vec3(0.0));
        auto dev = std::make_unique<SimulatedDevice>(std::move(profile), std::move(path), SimulatedHandParams{}, in.period_s);
        if (in.buttons) dev->set_button_script(*in.buttons);
        return dev;
    });
}

void add_replay(DeviceRegistry& r) {
    DriverInfo info = named("replay", "plays a recording's device samples back (tridex replay)");
    info.profiles = {"omni", "wand", "6dof", "falcon"};
    info.caps.input = InputKind::kRecorded;
    info.caps.dof_in = 6;
    info.caps.dof_out = 3;
    r.add(info, [](const DeviceSpec& spec, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
        return std::make_unique<ReplayDevice>(profile_by_name(spec.profile), in.samples);
    });
}

// The Novint Falcon: FTDI vendor 0x0403, Novint product 0xcb48 (libnifalcon's udev rules), over libusb-1.0; and the
// same driver over the emulated Falcon, its grip held by the simulated hand.
void add_falcon(DeviceRegistry& r) {
    DriverInfo info = named("falcon", "Novint Falcon (3-DOF force, USB)", true);
    info.usb_ids = {{falcon::kVendorId, falcon::kProductId}};
    info.caps.input = InputKind::kHardware;
    info.caps.dof_in = 3;
    info.caps.dof_out = 3;
    info.caps.renders_forces = true;
    info.caps.servable = true;
    info.caps.takes_firmware = true;
    info.caps.fixed_profile = "falcon";
    // The grip's four buttons (bit i = grip button i): the workspace button, then the menu, undo and redo.
    info.caps.buttons = {{0, "button0", "workspace"}, {1, "button1", "menu"}, {2, "button2", "edit.undo"},
                         {3, "button3", "edit.redo"}};
    info.product = "Novint Falcon";
    info.stand_in = "falcon-emulator";
    r.add(info, [](const DeviceSpec& spec, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
        bool plugged = false;
        for (const auto& [id, where] : usb_devices())
            plugged = plugged || (id.vendor == falcon::kVendorId && id.product == falcon::kProductId &&
                                  (spec.serial.empty() || where == spec.serial));
        if (!plugged)
            throw Error("device.driver: no Novint Falcon is plugged in (USB 0403:cb48" +
                        (spec.serial.empty() ? std::string() : " at " + spec.serial) +
                        "); `tridex devices` lists what is; --device falcon-emulator runs without one");
        falcon::FalconDeviceOptions o;
        o.firmware_path = in.firmware;
        o.period_s = in.period_s;
        return std::make_unique<falcon::FalconDevice>(std::make_unique<falcon::FalconUsbTransport>(spec.serial), o);
    });
    DriverInfo emu = named("falcon-emulator",
                   "the Falcon driver over an emulated Falcon (protocol, firmware load, homing), its grip held by the "
                   "simulated hand");
    emu.profiles = {"falcon"};
    emu.caps = info.caps;
    emu.caps.input = InputKind::kScripted;
    r.add(emu, [](const DeviceSpec&, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
        falcon::FalconEmulatorConfig c;
        c.hand_path = in.hand_path;
        c.buttons = in.buttons;
        c.period_s = in.period_s;
        falcon::FalconDeviceOptions o;
        o.firmware_image = falcon::emulator_firmware_image();  // generated; never a vendor binary
        o.period_s = in.period_s;
        return std::make_unique<falcon::FalconDevice>(std::make_unique<falcon::FalconEmulator>(std::move(c)), o);
    });
}

void add_net(DeviceRegistry& r) {
    DriverInfo info = named("net",
                    "a device on another machine served by `tridex device-server` (--device net:HOST:PORT; "
                    "--haptic-rendering distributed or local)");
    info.caps.input = InputKind::kRemote;
    info.caps.dof_in = 6;
    info.caps.dof_out = 3;
    info.caps.renders_forces = true;
    info.caps.address_form = "HOST:PORT";
    info.caps.address_required = true;
    info.caps.seals_link = true;
    r.add(info, [](const DeviceSpec& spec, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
        std::string host;
        std::uint16_t port = 0;
        net::split_host_port(spec.serial, "--device net:HOST:PORT", host, port);
        net::NetDeviceOptions o;
        o.mode = net::rendering_mode_from(in.haptic_rendering);
        o.period_s = in.period_s;
        net::KeySettings keys;
        keys.key_file = in.key_file;
        keys.passphrase_env = in.passphrase_env;
        const std::optional<net::SessionKey> key = net::key_from_settings(keys);  // before connecting: errors first
        std::unique_ptr<net::DatagramLink> link = net::EnetLink::connect(host, port);
        if (key) link = std::make_unique<net::SealedLink>(std::move(link), *key, net::SealRole::kJoiner);
        auto dev = std::make_unique<net::NetDevice>(std::move(link), o);
        dev->wait_for_server(3.0);
        return dev;
    });
}

void add_mouse(DeviceRegistry& r) {
    DriverInfo info = named("mouse",
                    "the desk mouse as a virtual stylus: the app sets the hand from the cursor (no forces; the "
                    "profile's limits still bound what the loop sends)");
    info.profiles = kHandProfiles;
    info.caps.input = InputKind::kPointer;
    info.caps.dof_in = 3;
    info.caps.dof_out = 3;
    info.caps.engage_button = 1;  // mouse_buttons::kEngage, the left button
    info.caps.buttons = {{0, "right", "workspace"}, {1, "left", "engage"}};  // the middle button is the desk's menu
    info.caps.strokes_end_on_release = true;
    info.caps.switches_op = true;  // keys 1..7
    info.caps.app_sets_hand = true;
    r.add(info, [](const DeviceSpec& spec, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
        DeviceProfile profile = profile_by_name(spec.profile);
        profile.name = "mouse (" + profile.name + " limits)";
        return std::make_unique<MouseDevice>(std::move(profile), start_of(in), in.period_s);
    });
}

// A 6-DOF 3D mouse through spacenavd's socket: spec.serial, else $SPNAV_SOCKET, else /etc/spnavrc's socket (as
// libspnav), else the default. No USB ids: spacenavd finds the puck.
void add_spacemouse(DeviceRegistry& r) {
    DriverInfo info = named("spacemouse", "a 6-DOF 3D mouse through spacenavd (rate control of the stylus pose; no forces)");
    info.profiles = kHandProfiles;
    info.caps.input = InputKind::kRate;
    info.caps.dof_in = 6;
    info.caps.dof_out = 0;
    info.caps.buttons = {{0, "button0", "workspace"}, {1, "button1", "menu"}};  // spacenavd's numbering
    info.detect_now = [] {
        const char* env = std::getenv("SPNAV_SOCKET");
        return spnav_reachable(spnav_socket_path("", env ? env : "", kSpnavConfigFile));
    };
    const SpaceMouseParams d;
    info.caps.options = {
        {"max_speed_m_s", d.max_speed_m_s, 0.0, 2.0, true, "tip speed at full deflection of a translation axis, m/s"},
        {"max_rate_rad_s", d.max_rate_rad_s, 0.0, 20.0, true, "angular rate at full deflection of a rotation axis, rad/s"},
        {"dead_zone", d.dead_zone, 0.0, 0.9, false, "fraction of full scale below which an axis reads as zero"},
        {"full_scale", d.full_scale, 1.0, 32767.0, false, "axis value at full deflection, device counts"}};
    r.add(info, [](const DeviceSpec& spec, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
        DeviceProfile profile = profile_by_name(spec.profile);
        profile.name = "spacemouse (" + profile.name + " limits)";
        SpaceMouseParams p;
        p.max_speed_m_s = option_or(in, "max_speed_m_s", p.max_speed_m_s);
        p.max_rate_rad_s = option_or(in, "max_rate_rad_s", p.max_rate_rad_s);
        p.dead_zone = option_or(in, "dead_zone", p.dead_zone);
        p.full_scale = option_or(in, "full_scale", p.full_scale);
        const char* env = std::getenv("SPNAV_SOCKET");
        p.socket_path = spnav_socket_path(spec.serial, env ? env : "", kSpnavConfigFile);
        return std::make_unique<SpaceMouseDevice>(std::move(profile), start_of(in), in.period_s, std::move(p));
    });
}

// A DTrack-tracked Flystick or standard body as the tool (no haptic device): the session's receiver (shared with
// the head or the wand on the same port), else one of its own.
void add_tracked(DeviceRegistry& r) {
    for (const bool flystick : {true, false}) {
        DriverInfo info = named(flystick ? "flystick" : "tracked-body",
                        flystick ? "an ART DTrack Flystick as the tool (6df2; its trigger engages the tool; no forces)"
                                 : "an ART DTrack standard body as the tool (6d; always engaged; no forces)");
        info.profiles = {"tracked"};
        info.caps.input = InputKind::kTracked;
        info.caps.dof_in = 6;
        info.caps.dof_out = 0;
        info.caps.engage_button = 1;  // tracked_tool_buttons::kEngage: the trigger, or always for a body
        info.caps.strokes_end_on_release = flystick;
        if (flystick) {  // tracked_tool_button_bits: the trigger is kEngage (bit 1), DTrack button i is bit i + 1
            info.caps.buttons = {{1, "trigger", "engage"}, {2, "button1", "menu"}, {3, "button2", "edit.undo"},
                                 {4, "button3", "edit.redo"}, {5, "button4", "op.next"}};
            for (int i = 5; i <= 7; ++i) info.caps.buttons.push_back({i + 1, "button" + std::to_string(i), ""});
            info.caps.joystick = true;  // DTrack's controller 1, the joystick's y
        }
        info.caps.fixed_profile = "tracked";
        info.caps.address_form = "PORT[:ID]";
        info.caps.target_ids = flystick ? kDTrackKeptFlysticks : kDTrackKeptBodies;
        info.caps.target_kind = flystick ? "Flystick" : "body";
        r.add(info, [flystick](const DeviceSpec&, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
            TrackedToolParams p = in.tracked_tool;
            p.flystick = flystick;
            std::shared_ptr<DTrackReceiver> rx =
                in.dtrack ? in.dtrack : std::make_shared<DTrackReceiver>(in.dtrack_port, in.dtrack_bind);
            return std::make_unique<TrackedToolDevice>(tracked_tool_profile(), std::move(rx), p, in.period_s);
        });
    }
}

// A game controller through GLFW's gamepad API: rate control like the 3D mouse; A is the stylus button, Y switches
// the operation.
void add_gamepad(DeviceRegistry& r) {
    DriverInfo info = named("gamepad",
                            "a game controller through GLFW (sticks and triggers: rate control of the stylus pose; A = "
                            "stylus button, Y = next operation; no forces)");
    info.profiles = kHandProfiles;
    info.caps.input = InputKind::kRate;
    info.caps.dof_in = 6;
    info.caps.dof_out = 0;
    info.caps.workspace_button = 0;
    // gamepad_device_buttons: A the stylus button, B the menu, Y the next operation.
    info.caps.buttons = {{0, "A", "workspace"}, {1, "B", "menu"}, {2, "Y", "op.next"}};
    info.caps.switches_op = true;
    const GamepadParams d;
    info.caps.options = {
        {"max_speed_m_s", d.max_speed_m_s, 0.0, 2.0, true, "tip speed at full deflection of a stick or trigger, m/s"},
        {"max_rate_rad_s", d.max_rate_rad_s, 0.0, 20.0, true, "angular rate at full deflection, rad/s"},
        {"dead_zone", d.dead_zone, 0.0, 0.9, false, "fraction of full deflection below which an axis reads as zero"},
        {"joystick", 0.0, 0.0, 16.0, false, "GLFW joystick slot 1..16 to read; 0 = the first gamepad found"}};
    r.add(info, [](const DeviceSpec& spec, const DeviceInputs& in) -> std::unique_ptr<HapticDevice> {
        DeviceProfile profile = profile_by_name(spec.profile);
        profile.name = "gamepad (" + profile.name + " limits)";
        GamepadParams p;
        p.max_speed_m_s = option_or(in, "max_speed_m_s", p.max_speed_m_s);
        p.max_rate_rad_s = option_or(in, "max_rate_rad_s", p.max_rate_rad_s);
        p.dead_zone = option_or(in, "dead_zone", p.dead_zone);
        const int joystick = static_cast<int>(option_or(in, "joystick", 0.0)) - 1;
        if (!in.host) throw Error("gamepad: this session reads no game controllers (it has no window system host)");
        return std::make_unique<GamepadDevice>(std::move(profile), start_of(in), in.period_s, p,
                                               std::make_unique<HostGamepadSource>(*in.host, joystick));
    });
}

}  // namespace

const DeviceRegistry& builtin_registry() {
    static const DeviceRegistry registry = [] {
        DeviceRegistry r;
        add_simulated(r);
        add_replay(r);
        add_falcon(r);
        add_net(r);
        add_mouse(r);
        add_spacemouse(r);
        add_tracked(r);
        add_gamepad(r);
        return r;
    }();
    return registry;
}

}  // namespace tridex::devices
