// app/commands/device_server/device_server_command.cpp - `tridex device-server`: serve this machine's device.
#include <CLI/CLI.hpp>

#include <memory>

#include "app/commands/command.hpp"
#include "app/commands/device_server/device_server.hpp"

namespace tridex::app {
namespace {

CommandAction setup_device_server(CLI::App& cmd) {
    auto o = std::make_shared<DeviceServerOptions>();
    DeviceServerOptions& server = *o;
    cmd.add_option("--device", server.device, "Driver of the served device: simulated, falcon, falcon-emulator")
        ->capture_default_str();
    cmd.add_option("--profile", server.profile, "simulated: device profile omni, wand, 6dof or falcon")->capture_default_str();
    cmd.add_option("--listen", server.listen,
                   "HOST:PORT to listen on (0.0.0.0:PORT = every interface; port 0 = a free one, printed)")
        ->capture_default_str();
    cmd.add_option("--seconds", server.seconds, "Stop after S seconds (0 = until Ctrl+C)")->capture_default_str();
    cmd.add_flag("--once", server.once, "Stop when the first session ends");
    cmd.add_option("--falcon-firmware", server.falcon_firmware, "falcon: the firmware FILE from your own installation");
    cmd.add_option("--mesh", server.mesh, "simulated, falcon-emulator: the hand plays the demo stroke over this mesh")
        ->check(CLI::ExistingFile);
    cmd.add_option("--stroke-seconds", server.stroke_seconds,
                   "simulated, falcon-emulator: the stroke's length (the session's --seconds)")
        ->capture_default_str();
    cmd.add_option("--key-file", server.key_file,
                   "Seal the link with the key in FILE (32 raw bytes or 64 hex characters): only sessions holding "
                   "the same key connect");
    cmd.add_option("--passphrase-env", server.passphrase_env,
                   "Seal the link with the passphrase in the environment variable VAR (its name, never the passphrase: "
                   "it would show in `ps`)");
    return [o] {
        run_device_server(*o);
        return 0;
    };
}

const CommandRegistration kRegistration{
    {"device-server",
     "Own a haptic device on this machine and serve it to a session elsewhere (--device net:HOST:PORT)", 70,
     setup_device_server}};

}  // namespace
}  // namespace tridex::app
