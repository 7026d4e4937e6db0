// The device server on its own thread and the net driver over ENet on loopback (real time, threads: part of the
// ThreadSanitizer set): both rendering modes, the server's watchdog, a dead server, a restarted one, a session that
// loads for seconds before its loop starts. Every wait for a thread is on a condition with a generous time-out.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <atomic>
#include <thread>

#include "core/error.hpp"
#include "devices/net/enet_link.hpp"
#include "devices/net/net_device.hpp"
#include "devices/simulated_device.hpp"
#include "haptics/device_server.hpp"
#include "surfaces.hpp"
#include "../devices/udp_flood.hpp"

namespace tridex::haptics {
namespace {

namespace net = devices::net;
using Clock = std::chrono::steady_clock;

constexpr double kTimeoutS = 20.0;

// Listens on a free loopback port near one derived from the process id.
std::unique_ptr<net::EnetLink> listen_somewhere(std::uint16_t& port) {
    for (int i = 0; i < 50; ++i) {
        port = static_cast<std::uint16_t>(42000 + (getpid() * 7 + i * 13) % 20000);
        try {
            return net::EnetLink::listen("127.0.0.1", port);
        } catch (const Error&) {
        }
    }
    throw Error("no free loopback port");
}

// Runs one client tick (read, then write `force`) every millisecond until done() or the time-out; true when done.
bool drive(net::NetDevice& client, const Vec3& force, const std::function<bool()>& done,
           const std::function<void()>& each = {}) {
    const auto end = Clock::now() + std::chrono::duration<double>(kTimeoutS);
    devices::DeviceState s;
    while (Clock::now() < end) {
        if (client.read(s)) {
            if (each) each();
            client.write(force, Vec3(0.0));
        }
        if (done()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return false;
}

struct EnetRig {
    devices::SimulatedDevice device{devices::DeviceProfile::phantom_omni(), devices::ScriptedPath::hold(Vec3(0.0))};
    std::uint16_t port = 0;
    std::unique_ptr<net::EnetLink> server_link;
    std::unique_ptr<DeviceServer> server;

    void start_server(bool same_port) {
        if (same_port)
            server_link = net::EnetLink::listen("127.0.0.1", port);
        else
            server_link = listen_somewhere(port);
        server = std::make_unique<DeviceServer>(device, *server_link, DeviceServerConfig{});
        server->start();
    }
    void stop_server() {
        server->stop();
        server.reset();
        server_link.reset();
    }
    // A client welcomed by the server; enabled (its loop running) unless `enable` is false; `watchdog_s` as
    // NetDeviceOptions (0: its default).
    std::unique_ptr<net::NetDevice> client(net::RenderingMode mode, bool enable = true, double watchdog_s = 0.0) {
        net::NetDeviceOptions o;
        o.mode = mode;
        o.give_up_s = 60.0;
        if (watchdog_s > 0.0) o.watchdog_s = watchdog_s;
        auto c = std::make_unique<net::NetDevice>(net::EnetLink::connect("127.0.0.1", port, 0.5), o);
        c->wait_for_server(kTimeoutS);
        if (enable) c->bring_up();
        return c;
    }
};

TEST(DeviceServerEnet, DistributedOverLoopback) {
    EnetRig rig;
    rig.start_server(false);
    auto client = rig.client(net::RenderingMode::kDistributed);
    EXPECT_EQ(client->profile().name, devices::DeviceProfile::phantom_omni().name);
    ASSERT_TRUE(drive(*client, Vec3(0.0, 0.0, 0.2), [&] { return client->link_stats().exchanges >= 300; }));
    const devices::DeviceLinkStats st = client->link_stats();
    EXPECT_GT(st.rtt_median_us, 0.0);
    EXPECT_GE(st.rtt_p99_us, st.rtt_median_us);
    EXPECT_GT(st.rate_hz, 100.0);
    EXPECT_EQ(rig.server->stats().sessions, 1u);
    EXPECT_EQ(rig.server->stats().malformed, 0u);
    rig.stop_server();
    EXPECT_EQ(rig.device.last_force_n(), Vec3(0.0)) << "stop() must leave zero force";
}

// Datagrams from another address while a session is connected (random bytes, a replay of state datagrams under the
// session's peer id, connects) are each counted as foreign and never reach the server; the session is served on.
TEST(DeviceServerEnet, AFloodFromAnotherAddressIsCountedAndDropped) {
    EnetRig rig;
    rig.start_server(false);
    // The link counts as down after 50 ms of silence, not the default 10 ms: the flooder, the server, the client and
    // other tests share 2 cores here, whose own wake-ups reach several ms; a flood that reached the session would
    // stall it far longer.
    auto client = rig.client(net::RenderingMode::kDistributed, true, 0.05);
    ASSERT_TRUE(drive(*client, Vec3(0.0), [&] { return client->link_stats().exchanges >= 100; }));
    const std::uint64_t foreign_before = rig.server->stats().foreign;
    const std::uint64_t drops_before = test::udp_drops(rig.port);
    constexpr int kFlood = 3000;
    std::atomic<bool> flooded{false};
    std::thread flooder([&] {
        test::UdpFlooder f(rig.port, 11);
        for (int i = 0; i < kFlood; ++i) {
            const int kind = i % 3;
            f.send(kind == 0 ? f.random_bytes() : kind == 1 ? f.enet_replayed_send() : f.enet_connect());
            if (i % 4 == 3) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        flooded = true;
    });
    const std::uint64_t exchanges0 = client->link_stats().exchanges;
    const bool served = drive(*client, Vec3(0.0, 0.0, 0.1), [&] {
        return flooded.load() && client->link_stats().exchanges >= exchanges0 + 300;
    });
    flooder.join();
    ASSERT_TRUE(served);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the server's last drain
    const DeviceServerStats st = rig.server->stats();
    const std::uint64_t dropped_by_kernel = test::udp_drops(rig.port) - drops_before;
    EXPECT_EQ(st.foreign - foreign_before + dropped_by_kernel, static_cast<std::uint64_t>(kFlood))
        << "foreign " << st.foreign - foreign_before << ", dropped by the kernel " << dropped_by_kernel;
    EXPECT_GE(st.datagrams, st.foreign);
    EXPECT_EQ(st.sessions, 1u);
    EXPECT_EQ(st.malformed, 0u) << "a flooded datagram reached the server";
    EXPECT_TRUE(st.session);
    EXPECT_EQ(client->link_stats().link_outages, 0u);
    rig.stop_server();
}

TEST(DeviceServerEnet, LocalOverLoopbackGetsTheSnapshot) {
    EnetRig rig;
    rig.start_server(false);
    auto client = rig.client(net::RenderingMode::kLocal);
    client->set_contact(net::ContactMsg{});
    // A full-size snapshot (every ray of the three windows with four intervals), a new one every tick as a busy
    // sculpt thread publishes: the driver sends the newest at most every 20 ms, and states keep flowing.
    auto wall = test::make_surface(1e-3, Vec3(-0.016, -0.016, -0.020));
    for (int a = 0; a < 3; ++a)
        test::fill_set(*wall, a, 0, 0, [](int, int) {
            return test::Intervals{{0.0f, 5.0f}, {6.0f, 7.0f}, {8.0f, 9.0f}, {10.0f, 20.0f}};
        });
    ASSERT_TRUE(drive(
        *client, Vec3(0.0),
        [&] { return rig.server->stats().snapshots >= 5 && client->link_stats().exchanges >= 300; },
        [&] {
            ++wall->sequence;
            client->observe_surface(*wall);
        }))
        << client->link_stats().link_events;
    EXPECT_EQ(client->link_stats().link_mode, "local");
    EXPECT_EQ(rig.server->stats().malformed, 0u);
    rig.stop_server();
}

TEST(DeviceServerEnet, WatchdogDeadServerAndRestart) {
    EnetRig rig;
    rig.start_server(false);
    auto client = rig.client(net::RenderingMode::kDistributed);
    ASSERT_TRUE(drive(*client, Vec3(0.1, 0.0, 0.0), [&] { return client->link_stats().exchanges >= 50; }));
    // The session falls silent: the server's watchdog zeroes the force.
    const auto end = Clock::now() + std::chrono::duration<double>(kTimeoutS);
    while (rig.server->stats().watchdog_trips == 0 && Clock::now() < end)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    EXPECT_EQ(rig.server->stats().watchdog_trips, 1u);
    // The server dies: the client's link goes down and says so.
    rig.stop_server();
    ASSERT_TRUE(drive(*client, Vec3(0.1, 0.0, 0.0), [&] { return client->link_down(); }));
    EXPECT_NE(client->link_stats().link_events.find("force zeroed"), std::string::npos);
    // A server on the same port again: the client reconnects, is welcomed and gets states again.
    rig.start_server(true);
    ASSERT_TRUE(drive(*client, Vec3(0.1, 0.0, 0.0), [&] { return !client->link_down(); }));
    EXPECT_EQ(rig.server->stats().sessions, 1u);
    EXPECT_NE(client->link_stats().link_events.find("welcomed this session again"), std::string::npos)
        << client->link_stats().link_events;
    rig.stop_server();
}

class SessionThatLoads : public ::testing::TestWithParam<net::RenderingMode> {};

TEST_P(SessionThatLoads, ForSecondsIsServedWhenItsLoopStarts) {
    EnetRig rig;
    rig.start_server(false);
    auto client = rig.client(GetParam(), false);
    client->set_contact(net::ContactMsg{});
    // The session loads its workpiece (a blocking set-up on this thread), five times ENet's peer time-out, before its
    // loop starts: the driver's link thread keeps the connection alive meanwhile.
    std::this_thread::sleep_for(std::chrono::milliseconds(2500));
    client->bring_up();
    auto wall = test::make_surface(1e-3, Vec3(-0.016, -0.016, -0.020));
    for (int a = 0; a < 3; ++a)
        test::fill_set(*wall, a, 0, 0, [](int, int) { return test::Intervals{{0.0f, 5.0f}, {6.0f, 7.0f}, {8.0f, 9.0f}}; });
    std::uint64_t seq = 1;
    ASSERT_TRUE(drive(
        *client, Vec3(0.0, 0.0, 0.2), [&] { return client->link_stats().exchanges >= 300; },
        [&] {
            wall->sequence = ++seq / 20 + 1;  // a new snapshot every 20 ticks, as a sculpting session publishes
            client->observe_surface(*wall);
        }))
        << client->link_stats().link_events;
    // The connection survived the set-up: one session, never timed out and welcomed again.
    EXPECT_EQ(rig.server->stats().sessions, 1u) << client->link_stats().link_events;
    EXPECT_EQ(client->link_stats().link_events.find("disconnected"), std::string::npos)
        << client->link_stats().link_events;
    rig.stop_server();
}

INSTANTIATE_TEST_SUITE_P(DeviceServerEnet, SessionThatLoads,
                         ::testing::Values(net::RenderingMode::kDistributed, net::RenderingMode::kLocal));

}  // namespace
}  // namespace tridex::haptics
