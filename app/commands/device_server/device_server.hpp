// app/commands/device_server/device_server.hpp - `tridex device-server`: a haptic device served to another machine.
#pragma once

#include <string>

namespace tridex::app {

/// Options of `tridex device-server`.
struct DeviceServerOptions {
    std::string device = "simulated";     ///< registry driver of the served device (simulated, falcon, falcon-emulator, ...)
    std::string profile = "omni";         ///< simulated: the device profile (omni, wand, 6dof, falcon)
    std::string listen = "127.0.0.1:7400";  ///< HOST:PORT to listen on (0.0.0.0 = every interface; port 0 = a free one)
    double seconds = 0.0;                 ///< stop after this long, s (0 = until Ctrl+C)
    bool once = false;                    ///< stop when the first session ends
    std::string falcon_firmware;          ///< falcon: the firmware file from the user's own installation
    /// simulated, falcon-emulator: the hand plays the stroke `tridex demo` plans over this mesh ("" = the bunny) ...
    std::string mesh;
    double stroke_seconds = 4.0;          ///< ... lasting this long, s (the session's --seconds)
    /// The key that seals the link (devices/net/sealed_link.hpp): a key file, or the name of the environment
    /// variable holding a passphrase; neither = the link is not authenticated (anyone who reaches it drives the device).
    std::string key_file;
    std::string passphrase_env;  ///< see key_file
};

/// Serves the device until Ctrl+C, `seconds`, the end of the first session (`once`) or the device's loss. Prints
/// one line per event (session connected, refused, silent link, ...), a line saying whether the link is sealed, and
/// a summary (with a sealed link, what it refused: hellos of another key, unsealed or forged datagrams). Throws
/// tridex::Error on bad options (a key file it cannot read, an unset or empty passphrase variable, naming the
/// option), a device that cannot be made, or an address it cannot listen on.
void run_device_server(const DeviceServerOptions& options);

}  // namespace tridex::app
