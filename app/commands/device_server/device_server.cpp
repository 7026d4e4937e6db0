// app/commands/device_server/device_server.cpp - `tridex device-server`: a device, an ENet listener, a server thread.
#include "app/commands/device_server/device_server.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include "app/commands/demo/demo.hpp"
#include "app/session/runtime/frame_loop.hpp"
#include "app/support/stop_signal.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "devices/registry/device_registry.hpp"
#include "devices/net/enet_link.hpp"
#include "devices/net/sealed_link.hpp"
#include "haptics/device_server.hpp"

namespace tridex::app {

namespace {

// What a sealed link refused, by reason, for the server's lines: "3 refused (hello_refused 2, bad_version 1)".
std::string seal_refusals(const devices::net::SealStats& s) {
    std::string out = std::to_string(s.refused()) + " refused";
    const std::pair<const char*, std::uint64_t> reasons[] = {
        {"hello_refused", s.hello_refused}, {"forged", s.forged},           {"replayed", s.replayed},
        {"out_of_order", s.out_of_order},   {"truncated", s.truncated},     {"bad_version", s.bad_version},
        {"early", s.early}};
    std::string parts;
    for (const auto& [name, n] : reasons)
        if (n > 0) parts += (parts.empty() ? "" : ", ") + std::string(name) + " " + std::to_string(n);
    return parts.empty() ? out : out + " (" + parts + ")";
}

}  // namespace

void run_device_server(const DeviceServerOptions& o) {
    if (!(o.seconds >= 0.0 && o.seconds <= 1e6))
        throw Error("--seconds: must be between 0 (until Ctrl+C) and 1e6, got " + format_number(o.seconds));
    const devices::DeviceRegistry& registry = devices::builtin_registry();
    std::vector<std::string> servable;
    for (const devices::DriverInfo& d : registry.drivers())
        if (d.available && d.caps.servable) servable.push_back(d.name);
    const devices::DriverInfo* driver = registry.find(o.device.substr(0, o.device.find(':')));
    if (driver && driver->caps.input == devices::InputKind::kRemote)
        throw Error("--device " + o.device + ": a device server serves a device, not a link");
    if (!driver || !driver->available || !driver->caps.servable)
        throw Error("--device: a device server serves " + devices::join_or(servable) + ", got '" + o.device + "'");
    const devices::DriverCapabilities& caps = driver->caps;
    if (caps.fixed_profile.empty()) {
        const bool known = std::find(driver->profiles.begin(), driver->profiles.end(), o.profile) != driver->profiles.end();
        if (!known) throw Error("--profile: unknown profile '" + o.profile + "'; use " + devices::join_or(driver->profiles));
    }
    std::string host;
    std::uint16_t port = 0;
    devices::net::split_host_port(o.listen, "--listen", host, port, true);
    devices::net::KeySettings keys;
    keys.key_file = o.key_file;
    keys.passphrase_env = o.passphrase_env;
    const std::optional<devices::net::SessionKey> key = devices::net::key_from_settings(keys);  // before slow work

    devices::DeviceSpec spec;
    spec.driver = o.device;
    spec.profile = caps.fixed_profile.empty() ? o.profile : caps.fixed_profile;
    devices::DeviceInputs inputs;
    if (caps.input == devices::InputKind::kScripted) {  // the simulated hand plays the demo's stroke
        std::printf("device-server: planning the demo stroke the simulated hand plays...\n");
        std::fflush(stdout);
        DemoOptions d;
        d.mesh = o.mesh;
        d.seconds = o.stroke_seconds;

        if (!(o.stroke_seconds >= 0.5 && o.stroke_seconds <= 600.0))  // the demo's --seconds range
            throw Error("--stroke-seconds: must be between 0.5 and 600, got " + format_number(o.stroke_seconds));
        inputs = demo_device_inputs(d, {spec.driver, spec.profile, ""});
    }
    if (!o.falcon_firmware.empty() && !caps.takes_firmware)
        throw Error("--falcon-firmware: the '" + driver->name + "' driver loads no firmware");
    inputs.firmware = o.falcon_firmware;
    std::unique_ptr<devices::HapticDevice> device = devices::builtin_registry().create(spec, inputs);
    std::unique_ptr<devices::net::DatagramLink> link = devices::net::EnetLink::listen(host, port);
    const devices::net::SealedLink* sealed = nullptr;  // owned by `link`
    if (key) {
        auto s = std::make_unique<devices::net::SealedLink>(std::move(link), *key, devices::net::SealRole::kListener);
        sealed = s.get();
        link = std::move(s);
    }

    haptics::DeviceServerConfig cfg;
    const auto t0 = std::chrono::steady_clock::now();
    const auto since = [t0] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    cfg.on_event = [&](const std::string& line) {
        std::printf("device-server %8.3f s: %s\n", since(), line.c_str());
        std::fflush(stdout);
    };
    cfg.request_realtime = true;
    haptics::DeviceServer server(*device, *link, cfg);
    install_stop_handlers();
    server.start();
    std::printf("device-server: serving '%s' (driver %s) on %s; sessions connect with --device net:%s\n",
                device->profile().name.c_str(), o.device.c_str(), link->where(), link->where());
    if (sealed)
        std::printf("device-server: the link is sealed with %s: only sessions holding the same key connect\n",
                    devices::net::key_source_text(keys).c_str());
    else
        std::printf("device-server: the link is not authenticated: anyone who reaches %s can drive the device "
                    "(seal it with --key-file or --passphrase-env)\n", link->where());
    std::fflush(stdout);
    std::uint64_t seal_refused_seen = 0;  // what the sealed link refused, as last reported
    // The server's frames, through the one frame loop every 20 ms: serving until a stop signal, --seconds, the device
    // lost or, with --once, the end of the first session. Nothing is drawn.
    bool had_session = false;
    FrameFunctions frames(
        [&] {
            if (!server.running() || stop_requested() || (o.seconds > 0.0 && since() >= o.seconds)) return false;
            const haptics::DeviceServerStats st = server.stats();
            had_session = had_session || st.session;
            if (sealed && sealed->stats().refused() > seal_refused_seen) {  // a session with another key, or none
                const devices::net::SealStats ss = sealed->stats();
                seal_refused_seen = ss.refused();
                cfg.on_event("the sealed link refused datagrams (another key, or an unsealed session?): " +
                             seal_refusals(ss) + " so far");
            }
            return !(o.once && had_session && !st.session);
        },
        [](std::uint64_t) { return false; }, [](std::uint64_t) {});
    run_frames(frames, FramePacing{0.020, true});
    server.stop();
    const haptics::DeviceServerStats st = server.stats();
    const std::string seal_line = sealed ? "sealed link: " + std::to_string(sealed->stats().accepted) + " accepted, " +
                                               seal_refusals(sealed->stats())
                                         : std::string("link not authenticated");
    std::printf("device-server: %llu sessions, %llu refused; %llu ticks; %llu datagrams received, %llu lost, "
                "%llu malformed (%s), %llu from other addresses dropped; %s; watchdog zeroed the force %llu times\n",
                static_cast<unsigned long long>(st.sessions), static_cast<unsigned long long>(st.refused),
                static_cast<unsigned long long>(st.ticks), static_cast<unsigned long long>(st.datagrams),
                static_cast<unsigned long long>(st.lost), static_cast<unsigned long long>(st.malformed),
                server.drops().summary().c_str(), static_cast<unsigned long long>(st.foreign),
                seal_line.c_str(),
                static_cast<unsigned long long>(st.watchdog_trips));
    if (st.device_lost) throw Error("device-server: the device was lost; serving stopped");
}

}  // namespace tridex::app
