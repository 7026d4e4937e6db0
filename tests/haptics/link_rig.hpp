// tests/haptics/link_rig.hpp - a device server and a net client over the in-process link shim on a simulated
// clock: a simulated device on the server, one server tick per millisecond.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "devices/net/link_shim.hpp"
#include "devices/net/net_device.hpp"
#include "devices/simulated_device.hpp"
#include "haptics/device_server.hpp"

namespace tridex::test {

struct LinkRig {
    double now = 0.0;
    devices::net::LinkShim shim;
    devices::SimulatedDevice device;
    std::unique_ptr<devices::net::DatagramLink> server_link;
    std::unique_ptr<haptics::DeviceServer> server;
    std::unique_ptr<devices::net::NetDevice> client;
    std::vector<std::string> server_events;  ///< what the server logged (its on_event lines)

    LinkRig(devices::net::RenderingMode mode, devices::ScriptedPath path, devices::net::ShimConfig link = {},
            std::uint16_t client_version = devices::net::kLinkVersion)
        : shim(link, [this] { return now; }), device(devices::DeviceProfile::phantom_omni(), std::move(path)) {
        start_server();
        devices::net::NetDeviceOptions o;
        o.mode = mode;
        o.clock = [this] { return now; };
        o.version = client_version;
        o.give_up_s = 0.5;
        o.link_thread = false;  // the simulated clock is the test thread's: it calls service() itself
        client = std::make_unique<devices::net::NetDevice>(shim.client_end(), o);
    }
    /// A (new) server on the shim's server end.
    void start_server() {
        server_link = shim.server_end();
        haptics::DeviceServerConfig c;
        c.clock = [this] { return now; };
        c.on_event = [this](const std::string& line) { server_events.push_back(line); };
        server = std::make_unique<haptics::DeviceServer>(device, *server_link, c);
    }
    /// The server gone: its end of the link closed.
    void kill_server() {
        server.reset();
        server_link.reset();
    }
    /// Advances the clock one millisecond and runs one server tick (when there is a server).
    void server_tick() {
        now += 1e-3;
        if (server) server->tick(now);
    }
    /// Ticks until the client is welcomed and has a state; false after `ticks` ticks.
    bool connect(int ticks = 200) {
        for (int i = 0; i < ticks; ++i) {
            server_tick();
            if (client->handshake()) return true;
        }
        return false;
    }
};

}  // namespace tridex::test
