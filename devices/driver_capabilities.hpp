// devices/driver_capabilities.hpp - what a driver says of itself, so that sessions, the overlay, the study, the
// device server and `tridex devices` read capabilities instead of comparing driver names.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace tridex::devices {

/// Where a driver's hand pose comes from.
enum class InputKind : std::uint8_t {
    kScripted,  ///< a simulated hand follows a scripted path (DeviceInputs::hand_path): tests, demos
    kRecorded,  ///< recorded samples played back (tridex replay only)
    kPointer,   ///< the desk pointer: the session sets the hand from the cursor every frame
    kRate,      ///< rate control: deflection sets the tool's velocity (3D mouse, game controller)
    kTracked,   ///< an optical tracker's target (DTrack): its device frame is the world
    kHardware,  ///< a haptic device that the person's hand moves (position control)
    kRemote,    ///< a device on another machine, served by `tridex device-server`
};

/// "scripted", "recorded", "pointer", "rate", "tracked", "hardware" or "remote".
std::string_view to_string(InputKind kind);

/// A numeric option a driver reads from a scene's "device" block (SI units), declared by the driver so that the
/// scene reader checks its range and names it in errors without knowing the driver.
struct DriverOption {
    std::string name;  ///< the field name in the scene's "device" object, e.g. "max_speed_m_s"
    double fallback = 0.0;      ///< value when the scene does not set it
    double min = 0.0, max = 0.0;  ///< accepted range (inclusive, except min when min_exclusive)
    bool min_exclusive = false;   ///< the value must be > min
    std::string doc;  ///< one line for docs/devices and error messages
};

/// One button of a device: its bit in DeviceState::buttons, the name a bindings file gives it, and the action it
/// does unless a bindings file says otherwise (an action name of the app's registry, app/actions/action_registry.hpp:
/// "engage", "workspace", "menu", "edit.undo", ...; "" = none).
struct ButtonInfo {
    int bit = 0;                 ///< 0..31
    std::string name;            ///< "trigger", "button1", "left", ...
    std::string default_action;  ///< "" = unbound
};

/// What a driver can do and needs. Buttons are bit indices of DeviceState::buttons. The workspace button is the
/// stylus button that the workspace techniques read (Peng's workspace moving, 4.1: held, the workspace follows the
/// hand; clutching: held, the hand moves without the tool).
struct DriverCapabilities {
    InputKind input = InputKind::kScripted;
    int dof_in = 0;                ///< sensed DOF of its default profile
    int dof_out = 0;               ///< actuated DOF of its default profile (0: renders no force)
    bool renders_forces = false;   ///< the device pushes back on the hand
    int workspace_button = 0;      ///< the stylus button the workspace techniques read, -1: none
    int engage_button = -1;        ///< the button that must be held for the tool to carve, -1: it always carves
    bool servable = false;         ///< `tridex device-server` can serve it to another machine
    bool strokes_end_on_release = false;  ///< a stroke ends when the engage button is released, not when idle
    bool switches_op = false;      ///< the person switches the tool's operation during the session (keys, buttons)
    bool app_sets_hand = false;    ///< the session sets the hand every frame (the pointer: MouseDevice::set_hand)
    bool takes_firmware = false;   ///< reads a firmware file from the user's installation (DeviceInputs::firmware)
    /// Its link can be authenticated and encrypted (devices/net/sealed_link.hpp) with the key of
    /// DeviceInputs::key_file or passphrase_env (--key-file, --passphrase-env, a scene's device.key_file or
    /// device.passphrase_env).
    bool seals_link = false;
    /// What may follow "NAME:" on a command line (--device NAME:ADDRESS), for help texts: "HOST:PORT" (remote),
    /// "PORT[:ID]" (tracked); "" = nothing. The driver or the session reads it (DeviceSpec::serial for remote).
    std::string address_form;
    bool address_required = false;  ///< the driver needs the address (net:HOST:PORT)
    int target_ids = 0;            ///< tracked: IDs 0..target_ids-1 of its kind of target (ADDRESS's ID)
    std::string target_kind;       ///< tracked: the kind of target its ID numbers ("Flystick", "body")
    std::string fixed_profile;     ///< the profile it always drives ("falcon", "tracked"); "" = the spec's
    std::vector<DriverOption> options;  ///< numeric options of a scene's "device" block it reads
    /// The device's buttons, with their default actions (the engage and workspace buttons above among them, bound to
    /// "engage" and "workspace"); a bindings file names them by ButtonInfo::name. Empty: it has none to bind.
    std::vector<ButtonInfo> buttons;
    bool joystick = false;  ///< DeviceState::joystick_y is a joystick's (a bindings file may bind it; default tool.scale)
};

/// True when a person moves the hand continuously outside any script (pointer, rate, tracked): such a session has
/// no scripted stroke and no "fit" workspace scale.
inline bool person_moves_hand(InputKind kind) {
    return kind == InputKind::kPointer || kind == InputKind::kRate || kind == InputKind::kTracked;
}

}  // namespace tridex::devices
