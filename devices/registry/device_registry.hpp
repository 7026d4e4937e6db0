// devices/registry/device_registry.hpp - creates a HapticDevice from a spec by driver name, and lists the drivers and
// the hardware that is plugged in.
//
// How to add a driver (the style of CHAI3D's custom-device template):
//   1. Write `devices/<name>_device.{hpp,cpp}`: a class deriving HapticDevice (devices/haptic_device.hpp).
//      - profile(): a DeviceProfile with the product's published workspace, continuous force and torque limits,
//        stable stiffness and DOF (cite the specification sheet in its docstring).
//      - on_open() / on_close(): connect and disconnect (libusb-1.0 for USB devices; a transport belongs under
//        the driver, never above it). Throw tridex::Error naming the unit and what the user can do.
//      - on_home(): calibrate the encoders; throw tridex::Error saying how to home (e.g. "push the grip in").
//      - on_enable() / on_disable(): amplifiers on and off, if the hardware has them.
//      - do_read(): the newest sample in the device frame, SI units, with the device's own time stamp; false
//        when the unit vanished. Never block longer than a fraction of a millisecond, never allocate.
//      - do_write(): send the force (N) and torque (N*m); the base class has already gated it (enabled only),
//        bounded it by the profile's limits and replaced non-finite values by zero.
//      - Report over-temperature and transport errors through raise_fault().
//   2. Register it in `builtin_registry()` (devices/registry/builtin_drivers.cpp): a DriverInfo (name, summary,
//      hardware or not, the USB ids it drives so that `tridex devices` shows whether one is plugged in, and its
//      DriverCapabilities: input kind, DOF, forces, engage button, servable, the scene options it reads), and a
//      factory from DeviceSpec + DeviceInputs. Sessions, the overlay, the study and the device server read the
//      capabilities; nothing outside devices/ compares a driver's name.
//   3. Add a test in tests/devices/ driving it through the lifecycle against a fake transport.
// Scene files then select it with "device": {"driver": "<name>", ...}.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "devices/button_script.hpp"
#include "devices/device_host.hpp"
#include "devices/driver_capabilities.hpp"
#include "devices/haptic_device.hpp"
#include "devices/scripted_path.hpp"
#include "devices/tracking/tracked_tool_device.hpp"

namespace tridex::devices {

/// Which device a session uses: what a scene's "device" object and the demo's --device flag give.
struct DeviceSpec {
    std::string driver = "simulated";  ///< a registered driver name (simulated, replay, ...)
    std::string profile = "omni";      ///< device profile for drivers that take one (omni, wand, 6dof, falcon)
    std::string serial;  ///< which unit of a hardware driver ("" = the first one found; falcon: "bus B port P.Q")
};

/// What a session hands a driver besides its spec: the loop period and, for the software drivers, their input.
struct DeviceInputs {
    double period_s = 1e-3;                 ///< haptic loop period, s
    std::optional<ScriptedPath> hand_path;  ///< scripted input: the virtual hand's target path, device frame (m); others
                                            ///< take its start as the tip's first position
    std::optional<ButtonScript> buttons;    ///< scripted input: the buttons the hand presses, in device time
    std::vector<DeviceState> samples;       ///< recorded input: the samples, in order
    /// Drivers that take firmware (DriverCapabilities::takes_firmware): the file from the user's own installation
    /// (--falcon-firmware, a scene's "device.firmware"); "" = none (the driver then says in one line what it needs).
    std::string firmware;
    /// The driver's own numeric options (DriverCapabilities::options) that the scene set, by name, SI units; an
    /// option not here takes its fallback. The driver checks names and ranges again (throws tridex::Error).
    std::map<std::string, double> options;
    /// remote drivers: where the contact loop runs, "distributed" (here) or "local" (on the device server); see
    /// devices/net/net_device.hpp.
    std::string haptic_rendering = "distributed";
    /// Drivers whose link can be sealed (DriverCapabilities::seals_link): the key file (--key-file, a scene's
    /// "device.key_file") or the environment variable holding the passphrase (--passphrase-env, a scene's
    /// "device.passphrase_env"); both "" = the link is not authenticated. See docs/devices/sealed-link.md.
    std::string key_file;
    std::string passphrase_env;  ///< see key_file
    /// tracked drivers: the DTrack receiver to read (shared with the head or the wand on the same port); null = the
    /// driver opens one on dtrack_port / dtrack_bind.
    std::shared_ptr<DTrackReceiver> dtrack{};
    int dtrack_port = 5000;                 ///< UDP port when the driver opens its own receiver (1..65535; 0 = any)
    std::string dtrack_bind = "0.0.0.0";    ///< local IPv4 address it listens on
    /// tracked drivers: which target and how (its `flystick` flag is set by the driver).
    TrackedToolParams tracked_tool{};
    /// The session's window-system input (game controllers), for drivers that read it; null = the session offers
    /// none (such a driver then says so when it is created).
    DeviceHost* host = nullptr;
};

/// A USB vendor and product id pair.
struct UsbId {
    std::uint16_t vendor = 0;
    std::uint16_t product = 0;
};

/// What a driver says of itself: `tridex devices` lists it, sessions read its capabilities.
struct DriverInfo {
    std::string name;                   ///< the driver name a spec uses
    std::string summary;                ///< one line: what it drives
    bool hardware = false;              ///< true for drivers of physical devices
    bool available = true;              ///< false: known hardware that this build cannot drive yet
    std::vector<std::string> profiles;  ///< profile names it accepts (empty: the hardware's own)
    std::vector<UsbId> usb_ids;         ///< the USB ids of the hardware it drives
    DriverCapabilities caps;            ///< input kind, DOF, forces, engage button, servable, options
    std::string product;                ///< hardware: the product's name for messages ("Novint Falcon")
    std::string stand_in;               ///< hardware: a driver that runs the same without the hardware, or ""
    /// Whether what the driver reads is there now (a daemon's socket answers): "" when it is, else one line saying
    /// what is missing ("no spacenavd at /var/run/spnav.sock"). Empty function: nothing to find (a software driver,
    /// or one whose source shows itself only once a session runs). Hardware is found by its USB ids (detect()).
    std::function<std::string()> detect_now;
};

/// A driver chosen on a command line (`--device TEXT`): its name, profile and address.
struct DeviceChoice {
    std::string driver;   ///< a registered driver name
    std::string profile;  ///< the profile to use ("" = the scene's or the driver's own)
    std::string address;  ///< what followed "NAME:" (HOST:PORT for remote drivers, PORT[:ID] for tracked ones), or ""
};

/// One plugged-in unit of known hardware.
struct DetectedDevice {
    std::string driver;    ///< the driver that handles it
    std::string product;   ///< the product name (from the driver's summary)
    UsbId id;              ///< its USB ids
    std::string location;  ///< "bus B port P.Q" (libusb numbering)
};

/// "a, b or c" (one name: itself; none: "").
std::string join_or(const std::vector<std::string>& names);

/// "vvvv:pppp" in lower-case hex, as lsusb prints it.
std::string usb_id_string(const UsbId& id);

/// Lists the plugged-in USB devices' ids and locations (libusb-1.0). Returns an empty list when USB cannot be
/// enumerated (no permission, no USB in a container) and puts the reason in `error` (may be null).
std::vector<std::pair<UsbId, std::string>> usb_devices(std::string* error = nullptr);

/// Driver name -> factory. Thread-compatible (fill it once, then read from any thread).
class DeviceRegistry {
public:
    /// Makes a closed device from a spec; throws tridex::Error naming the field on a bad spec.
    using Factory = std::function<std::unique_ptr<HapticDevice>(const DeviceSpec&, const DeviceInputs&)>;

    /// Adds a driver; throws tridex::Error when the name is empty or taken.
    void add(DriverInfo info, Factory factory);
    /// A closed device (open(), home() and enable() are the caller's, see HapticDevice) from `spec`. Throws
    /// tridex::Error "device.driver: unknown driver 'x'; drivers: a, b" for an unknown driver, "device.driver:
    /// the '<name>' driver is not available in this build" for known hardware without a driver, and whatever the
    /// factory throws for a bad profile or missing input.
    std::unique_ptr<HapticDevice> create(const DeviceSpec& spec, const DeviceInputs& inputs) const;
    /// Every registered driver, in registration order.
    std::vector<DriverInfo> drivers() const;
    /// The driver named `name`, or null.
    const DriverInfo* find(const std::string& name) const;
    /// The driver named `name`; throws tridex::Error "FIELD: unknown driver 'x'; drivers: a, b" (FIELD = `field`).
    const DriverInfo& info(const std::string& name, const std::string& field = "device.driver") const;
    /// Which drivers a command accepts (null = every available one but the recorded).
    using DriverFilter = std::function<bool(const DriverInfo&)>;
    /// Reads a command line's `--device TEXT`: a profile of the default driver (the first scripted driver with
    /// profiles, the simulated hand: "omni", "wand", "6dof"), a driver name ("falcon", "mouse"), or NAME:ADDRESS
    /// for a driver with an address form ("net:HOST:PORT", "flystick:5000:1"). A name that is both a driver and a
    /// profile ("falcon") is the driver. Throws tridex::Error "OPTION: unknown device 'x'; use a, b or c" (OPTION =
    /// `option`, the list from choices(usable)) for a name that is neither or a driver `usable` refuses, and names
    /// the driver when its address is missing or it takes none.
    DeviceChoice choose(const std::string& text, const std::string& option, const DriverFilter& usable = {}) const;
    /// What choose() accepts, for help and error texts: the default driver's profiles (when usable and not also a
    /// driver's name), then each usable driver but the default as NAME, NAME:FORM or NAME[:FORM].
    std::vector<std::string> choices(const DriverFilter& usable = {}) const;
    /// The plugged-in units of the registered hardware drivers (USB ids matched against usb_devices()); `error`
    /// (may be null) gets why USB could not be listed.
    std::vector<DetectedDevice> detect(std::string* error = nullptr) const;

private:
    struct Entry {
        DriverInfo info;
        Factory factory;
    };
    std::vector<Entry> entries_;
};

/// The drivers this build has: `simulated` (the closed-loop virtual hand, profiles omni, wand, 6dof, falcon),
/// `replay` (recorded samples), `falcon` (a Novint Falcon over libusb-1.0, USB 0403:cb48: creating it throws
/// "no Novint Falcon is plugged in" when libusb finds none) and `falcon-emulator` (the same driver over the in-memory
/// Falcon of devices/falcon/falcon_emulator.hpp, its grip held by the simulated hand on DeviceInputs::hand_path),
/// `net` (a device served by `tridex device-server` at DeviceSpec::serial = "HOST:PORT": creating it waits up to 3 s
/// for the server's welcome and throws when none answers, it refuses or the sealed link's handshake fails; with
/// DeviceInputs::key_file or passphrase_env its link is a SealedLink), `mouse` (the desk mouse) and `spacemouse` (a 3D mouse through spacenavd's socket: DeviceSpec::serial, else
/// $SPNAV_SOCKET, else /etc/spnavrc's `socket`, else /var/run/spnav.sock; opening it throws when no daemon listens there).
const DeviceRegistry& builtin_registry();

/// The profile named `name` (omni, wand, 6dof, falcon, tracked); throws tridex::Error "device.profile: unknown
/// profile 'x'; use omni, wand, 6dof, falcon or tracked".
DeviceProfile profile_by_name(const std::string& name);

/// The profile name (omni, wand, 6dof, falcon) whose DeviceProfile::name is `product` (a recording's device_name), or
/// "" when none is.
std::string profile_name_of(const std::string& product);

}  // namespace tridex::devices
