// The device server and the net driver over the in-process link shim (simulated clock): the handshake, forces
// through the link in distributed mode, the server's god-object in local mode, the watchdogs on both ends, a dead
// and a restarted server, a peer of another link version, malformed datagrams.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/spsc_ring.hpp"
#include "core/triple_buffer.hpp"
#include "devices/net/surface_codec.hpp"
#include "haptics/haptic_loop.hpp"
#include "link_rig.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

namespace net = devices::net;
using devices::ScriptedPath;
using test::LinkRig;

TEST(DeviceServer, DistributedForceReachesTheDevice) {
    LinkRig rig(net::RenderingMode::kDistributed, ScriptedPath::hold(Vec3(0.0)));
    ASSERT_TRUE(rig.connect());
    EXPECT_EQ(rig.client->profile().name, devices::DeviceProfile::phantom_omni().name);
    rig.client->bring_up();
    devices::DeviceState s;
    for (int i = 0; i < 20; ++i) {
        ASSERT_TRUE(rig.client->read(s));
        rig.client->write(Vec3(0.0, 0.0, 0.3), Vec3(0.0));
        rig.server_tick();
    }
    EXPECT_NEAR(rig.device.last_force_n().z, 0.3, 1e-12);
    const devices::DeviceLinkStats st = rig.client->link_stats();
    EXPECT_EQ(st.link_mode, "distributed");
    EXPECT_GT(st.exchanges, 15u);
    EXPECT_EQ(st.lost, 0u);
    EXPECT_EQ(st.link_outages, 0u);
    EXPECT_EQ(rig.server->stats().sessions, 1u);
}

TEST(DeviceServer, LatencyShowsInTheRoundTrip) {
    net::ShimConfig link;
    link.latency_s = 0.005;
    LinkRig rig(net::RenderingMode::kDistributed, ScriptedPath::hold(Vec3(0.0)), link);
    ASSERT_TRUE(rig.connect());
    rig.client->bring_up();
    devices::DeviceState s;
    for (int i = 0; i < 100; ++i) {
        ASSERT_TRUE(rig.client->read(s));
        rig.client->write(Vec3(0.0), Vec3(0.0));
        rig.server_tick();
    }
    const devices::DeviceLinkStats st = rig.client->link_stats();
    // Two 5 ms legs plus at most a tick of holding on each side.
    EXPECT_GE(st.rtt_median_us, 10000.0);
    EXPECT_LE(st.rtt_median_us, 12500.0);
    EXPECT_NEAR(st.rate_hz, 1000.0, 50.0);
}

TEST(DeviceServer, ServerWatchdogZeroesForceWithinTenMilliseconds) {
    LinkRig rig(net::RenderingMode::kDistributed, ScriptedPath::hold(Vec3(0.0)));
    ASSERT_TRUE(rig.connect());
    rig.client->bring_up();
    devices::DeviceState s;
    for (int i = 0; i < 10; ++i) {
        ASSERT_TRUE(rig.client->read(s));
        rig.client->write(Vec3(0.5, 0.0, 0.0), Vec3(0.0));
        rig.server_tick();
    }
    ASSERT_NEAR(rig.device.last_force_n().x, 0.5, 1e-12);
    const double last_send = rig.now;
    // The session falls silent; the server keeps ticking.
    while (rig.now - last_send < 0.0100 - 1e-9) rig.server_tick();
    EXPECT_EQ(rig.device.last_force_n(), Vec3(0.0)) << "force still on 10 ms after the last datagram";
    EXPECT_EQ(rig.server->stats().watchdog_trips, 1u);
}

TEST(DeviceServer, DeadServerClientZeroesForceAndSaysSo) {
    LinkRig rig(net::RenderingMode::kDistributed, ScriptedPath::hold(Vec3(0.0)));
    ASSERT_TRUE(rig.connect());
    rig.client->bring_up();
    devices::DeviceState s;
    for (int i = 0; i < 5; ++i) {
        ASSERT_TRUE(rig.client->read(s));
        rig.client->write(Vec3(0.2, 0.0, 0.0), Vec3(0.0));
        rig.server_tick();
    }
    rig.kill_server();
    ASSERT_TRUE(rig.client->read(s));  // the last state that was on its way
    const double t_before = s.t_s;
    bool down = false;
    for (int i = 0; i < 20 && !down; ++i) {
        rig.server_tick();
        ASSERT_TRUE(rig.client->read(s));
        EXPECT_EQ(s.t_s, t_before) << "a dead server's sample must not look fresh";
        rig.client->write(Vec3(0.2, 0.0, 0.0), Vec3(0.0));
        down = rig.client->link_down();
    }
    EXPECT_TRUE(down);
    EXPECT_NE(rig.client->status().faults & devices::kFaultIo, 0u);
    const devices::DeviceLinkStats st = rig.client->link_stats();
    EXPECT_EQ(st.link_outages, 1u);
    EXPECT_NE(st.link_events.find("force zeroed"), std::string::npos) << st.link_events;
    // After give_up_s (0.5 s here) the device counts as gone.
    bool gone = false;
    for (int i = 0; i < 1000 && !gone; ++i) {
        rig.server_tick();
        gone = !rig.client->read(s);
    }
    EXPECT_TRUE(gone);
}

TEST(DeviceServer, ServerRestartedMidSessionIsRejoined) {
    LinkRig rig(net::RenderingMode::kDistributed, ScriptedPath::hold(Vec3(0.0)));
    ASSERT_TRUE(rig.connect());
    rig.client->bring_up();
    devices::DeviceState s;
    for (int i = 0; i < 30; ++i) {
        ASSERT_TRUE(rig.client->read(s));
        rig.client->write(Vec3(0.1, 0.0, 0.0), Vec3(0.0));
        rig.server_tick();
    }
    rig.kill_server();
    for (int i = 0; i < 30; ++i) {
        rig.server_tick();
        ASSERT_TRUE(rig.client->read(s));
        rig.client->write(Vec3(0.1, 0.0, 0.0), Vec3(0.0));
    }
    ASSERT_TRUE(rig.client->link_down());
    const double t_down = s.t_s;
    rig.start_server();  // the device was disabled by the old server; the new one brings it up again
    bool up = false;
    for (int i = 0; i < 100 && !up; ++i) {
        rig.server_tick();
        ASSERT_TRUE(rig.client->read(s));
        rig.client->write(Vec3(0.1, 0.0, 0.0), Vec3(0.0));
        up = !rig.client->link_down();
    }
    ASSERT_TRUE(up);
    EXPECT_GT(s.t_s, t_down) << "time stamps must keep increasing across a server restart";
    for (int i = 0; i < 5; ++i) {
        ASSERT_TRUE(rig.client->read(s));
        rig.client->write(Vec3(0.1, 0.0, 0.0), Vec3(0.0));
        rig.server_tick();
    }
    EXPECT_NEAR(rig.device.last_force_n().x, 0.1, 1e-12);
    EXPECT_NE(rig.client->link_stats().link_events.find("welcomed this session again"), std::string::npos);
}

TEST(DeviceServer, OtherLinkVersionIsRefusedWithOneLine) {
    LinkRig rig(net::RenderingMode::kDistributed, ScriptedPath::hold(Vec3(0.0)), {}, net::kLinkVersion + 1);
    try {
        rig.connect();
        FAIL() << "a client of another link version was welcomed";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("speaks link version " + std::to_string(net::kLinkVersion) + ", this session speaks " +
                            std::to_string(net::kLinkVersion + 1)),
                  std::string::npos)
            << what;
        EXPECT_EQ(what.find('\n'), std::string::npos);
    }
    EXPECT_EQ(rig.server->stats().refused, 1u);
    EXPECT_EQ(rig.server->stats().sessions, 0u);
}

TEST(DeviceServer, MalformedDatagramsAreCountedAndDropped) {
    double now = 0.0;
    net::LinkShim shim({}, [&] { return now; });
    devices::SimulatedDevice device(devices::DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    auto server_link = shim.server_end();
    DeviceServerConfig c;
    c.clock = [&] { return now; };
    DeviceServer server(device, *server_link, c);
    auto peer = shim.client_end();
    std::vector<std::uint8_t> d;
    net::Header h;
    const auto send = [&](const std::vector<std::uint8_t>& bytes) {
        peer->send(bytes, false);
        now += 1e-3;
        server.tick(now);
    };
    send({1, 2, 3});  // shorter than a header
    net::encode(h, net::ForceMsg{Vec3(1.0), Vec3(0.0)}, d);
    d[0] ^= 0xff;
    send(d);  // bad magic
    net::encode(h, net::ForceMsg{Vec3(1.0), Vec3(0.0)}, d);
    d[6] = 99;
    send(d);  // unknown type
    net::encode(h, net::ForceMsg{Vec3(1.0), Vec3(0.0)}, d);
    send(d);  // well formed, but before any kHello
    net::encode(h, net::Hello{}, d);
    send(d);  // a session starts
    h.seq = 1;
    net::encode(h, net::ForceMsg{Vec3(1.0), Vec3(0.0)}, d);
    d.pop_back();
    send(d);  // torn
    h.seq = 2;
    net::encode(h, net::ForceMsg{Vec3(std::numeric_limits<double>::quiet_NaN()), Vec3(0.0)}, d);
    send(d);  // non-finite force
    h.seq = 3;
    net::ContactMsg contact;
    net::encode(h, contact, d);
    send(d);  // a local-mode message in a distributed session
    const net::DropCounts drops = server.drops();
    EXPECT_EQ(drops.total(), 7u) << drops.summary();
    EXPECT_EQ(server.stats().malformed, 7u);
    for (net::DropReason r : {net::DropReason::kTooShort, net::DropReason::kBadMagic, net::DropReason::kUnknownType,
                              net::DropReason::kBadLength, net::DropReason::kNonFinite})
        EXPECT_EQ(drops.by_reason[static_cast<int>(r)], 1u) << net::to_string(r);
    EXPECT_EQ(drops.by_reason[static_cast<int>(net::DropReason::kUnexpected)], 2u);
    EXPECT_EQ(device.last_force_n(), Vec3(0.0));
    EXPECT_NE(drops.summary().find("non-finite number: 1"), std::string::npos) << drops.summary();
}

// What the server tells a session counts from that session's start: a second session on the same server does not
// inherit the first one's malformed datagrams.
TEST(DeviceServer, EachSessionIsToldItsOwnCounts) {
    double now = 0.0;
    net::LinkShim shim({}, [&] { return now; });
    devices::SimulatedDevice device(devices::DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    auto server_link = shim.server_end();
    DeviceServerConfig c;
    c.clock = [&] { return now; };
    DeviceServer server(device, *server_link, c);
    auto peer = shim.client_end();
    std::vector<std::uint8_t> d;
    net::Header h;
    // The newest state message the server sent the peer (its counters), after one tick.
    const auto tick_and_read_state = [&](const std::vector<std::uint8_t>* send) {
        if (send) peer->send(*send, false);
        now += 1e-3;
        server.tick(now);
        net::LinkEvent ev;
        std::optional<net::StateMsg> last;
        while (peer->poll(ev)) {
            net::Header rh;
            net::StateMsg m;
            if (ev.kind == net::LinkEvent::kData &&
                net::decode_header(ev.data.data(), ev.data.size(), rh) == net::DropReason::kNone &&
                rh.type == net::MsgType::kState && net::decode(ev.data.data(), ev.data.size(), m) == net::DropReason::kNone)
                last = m;
        }
        return last;
    };
    net::encode(h, net::Hello{}, d);
    tick_and_read_state(&d);  // the first session
    for (std::uint32_t seq = 1; seq <= 3; ++seq) {
        h.seq = seq;
        net::encode(h, net::ForceMsg{Vec3(0.0), Vec3(0.0)}, d);
        d.pop_back();  // torn: malformed
        tick_and_read_state(&d);
    }
    // Heartbeats 5 and 9: three lost between them; then 15 ms of silence, a watchdog trip, and heartbeat 10.
    for (const std::uint32_t seq : {5u, 9u}) {
        h.seq = seq;
        net::encode_heartbeat(h, d);
        tick_and_read_state(&d);
    }
    for (int i = 0; i < 15; ++i) tick_and_read_state(nullptr);
    h.seq = 10;
    net::encode_heartbeat(h, d);
    tick_and_read_state(&d);
    std::optional<net::StateMsg> first;
    for (int i = 0; i < 5 && !first; ++i) first = tick_and_read_state(nullptr);
    ASSERT_TRUE(first);
    EXPECT_EQ(first->malformed, 3u);
    EXPECT_EQ(first->lost, 3u);
    EXPECT_EQ(first->watchdog_trips, 1u);
    h.seq = 0;
    net::encode(h, net::Hello{}, d);
    tick_and_read_state(&d);  // a second session on the same server
    std::optional<net::StateMsg> second;
    for (int i = 0; i < 5 && !second; ++i) second = tick_and_read_state(nullptr);
    ASSERT_TRUE(second);
    EXPECT_EQ(second->malformed, 0u);
    EXPECT_EQ(second->lost, 0u);
    EXPECT_EQ(second->watchdog_trips, 0u);
    EXPECT_EQ(second->stale_snapshots, 0u);
    EXPECT_EQ(server.stats().malformed, 3u);  // the server's own total keeps every session's
    EXPECT_EQ(server.stats().lost, 3u);
    EXPECT_EQ(server.stats().watchdog_trips, 1u);
    EXPECT_EQ(server.stats().sessions, 2u);
}

// A local-rendering session over the shim whose hand follows `path` toward a z = 0 wall (solid below it): sets
// `contact`, connects, brings the loop up, then runs `ticks` ticks offering the wall's snapshot; `before_tick(i)`
// runs first in each. Returns the lowest device z reached (m); the rig keeps the last force.
template <class BeforeTick>
double press_wall(LinkRig& rig, const net::ContactMsg& contact, int ticks, BeforeTick before_tick) {
    rig.client->set_contact(contact);
    EXPECT_TRUE(rig.connect());
    rig.client->bring_up();
    auto wall = test::make_surface(1e-3, Vec3(-0.016, -0.016, -0.020));
    test::fill_set(*wall, 2, 0, 0, [](int, int) { return test::Intervals{{0.0f, 20.0f}}; });
    wall->centre_m = Vec3(0.0);
    devices::DeviceState s;
    double min_z = 1.0;
    for (int i = 0; i < ticks; ++i) {
        before_tick(i);
        EXPECT_TRUE(rig.client->read(s));
        rig.client->observe_surface(*wall);
        rig.client->write(Vec3(0.0), Vec3(0.0));  // ignored in local mode
        rig.client->service();
        rig.server_tick();
        min_z = std::min(min_z, rig.device.position_m().z);
    }
    return min_z;
}

TEST(DeviceServer, LocalRenderingPushesBackNextToTheDevice) {
    // The hand goes from 10 mm above a z = 0 wall to 3 mm into it; the server's god-object pushes back.
    LinkRig rig(net::RenderingMode::kLocal,
                ScriptedPath({0.0, 0.2}, {Vec3(0.0, 0.0, 0.010), Vec3(0.0, 0.0, -0.003)}));
    net::ContactMsg contact;
    contact.stiffness_n_per_m = 700.0;
    contact.tool_radius_m = 0.0;
    const double min_z = press_wall(rig, contact, 600, [](int) {});
    EXPECT_GT(rig.device.last_force_n().z, 0.3) << "the wall does not push back";
    EXPECT_GT(min_z, -0.003) << "the tool went as deep as the hand: no wall";
    const DeviceServerStats st = rig.server->stats();
    EXPECT_EQ(st.snapshots, 1u);
    EXPECT_EQ(st.stale_snapshots, 0u);
    EXPECT_EQ(rig.client->link_stats().link_mode, "local");
}

TEST(DeviceServer, LocalRenderingSessionSculptsWithTheServersToolSamples) {
    // The hand presses 3 mm into a z = 0 wall. The session's own snapshot is empty, so any proxy on the wall in its
    // tool samples came from the server's god-object.
    LinkRig rig(net::RenderingMode::kLocal,
                ScriptedPath({0.0, 0.2}, {Vec3(0.0, 0.0, 0.010), Vec3(0.0, 0.0, -0.003)}));
    HapticLoopConfig cfg;
    cfg.contact.stiffness_n_per_m = 700.0;
    cfg.contact.tool_radius_m = 0.0;
    cfg.request_realtime = false;
    net::ContactMsg contact;
    contact.stiffness_n_per_m = cfg.contact.stiffness_n_per_m;
    contact.tool_radius_m = 0.0;
    rig.client->set_contact(contact);
    ASSERT_TRUE(rig.connect());
    auto wall = test::make_surface(1e-3, Vec3(-0.016, -0.016, -0.020));
    test::fill_set(*wall, 2, 0, 0, [](int, int) { return test::Intervals{{0.0f, 20.0f}}; });
    wall->centre_m = Vec3(0.0);
    TripleBuffer<ActiveSurface> session_surface;  // never published: no contact on the session's side
    SpscRing<ToolSample> samples(4096);
    HapticLoop loop(*rig.client, session_surface, samples, cfg);
    ToolSample last{}, deepest{};
    TickRecord rec;
    int remote = 0;
    for (int i = 0; i < 600; ++i) {
        rig.client->observe_surface(*wall);  // as the sculpt thread offers it
        rec = loop.step(rig.now);
        rig.client->service();
        rig.server_tick();
        devices::RemoteToolSample t;
        if (rig.client->remote_tool(t)) ++remote;
        while (samples.try_pop(last))
            if (last.position.z < deepest.position.z) deepest = last;
    }
    loop.stop();
    EXPECT_GT(remote, 500) << "the states carried no tool sample";
    // The server's god-object kept the proxy on the wall while the HIP went in, and the session sculpts with both.
    EXPECT_LT(deepest.position.z, -0.0005);
    EXPECT_GT(deepest.surface_m.z, -0.0002);
    EXPECT_NEAR(last.position.z, rig.device.position_m().z, 0.002);
    EXPECT_EQ(last.op, ToolOp::kSubtract);
    EXPECT_GT(rec.force_n.z, 0.3) << "the record shows the force the server rendered";
    EXPECT_GT(rec.proxy_m.z, -0.0002);
}

// The session's contact points reach the server's loop: the hand stops 2 mm above a z = 0 wall, so a tool whose
// contact point is its centre never touches it, while one whose contact point is 5 mm below the centre (its tip)
// presses into it and is pushed back.
TEST(DeviceServer, LocalRenderingUsesTheSessionsContactPoints) {
    struct Outcome {
        double force_z_n;
        double min_z_m;
    };
    auto press = [](const net::ContactMsg& contact) {
        LinkRig rig(net::RenderingMode::kLocal,
                    ScriptedPath({0.0, 0.2}, {Vec3(0.0, 0.0, 0.015), Vec3(0.0, 0.0, 0.002)}));
        const double min_z = press_wall(rig, contact, 600, [](int) {});
        return Outcome{rig.device.last_force_n().z, min_z};
    };
    net::ContactMsg centre;
    centre.stiffness_n_per_m = 700.0;
    net::ContactMsg tip = centre;
    tip.point_count = 1;
    tip.point_local_m[0] = Vec3(0.0, 0.0, -0.005);
    const Outcome c = press(centre), t = press(tip);
    EXPECT_NEAR(c.force_z_n, 0.0, 1e-9) << "the centre never reaches the wall";
    EXPECT_GT(t.force_z_n, 0.3) << "the tip presses into the wall and is pushed back";
    EXPECT_GT(t.min_z_m, 0.002 + 0.0005) << "the wall holds the tool above the hand's target";
}

// A tool resized during the session reaches the server: a contact point 2 mm below the centre stays 1 mm above the
// wall when the hand comes to rest 3 mm above it; resized to twice the size before the hand comes down, it ends
// 1 mm in the wall, and the server pushes back.
TEST(DeviceServer, LocalRenderingFollowsAResizedTool) {
    auto final_force_z = [](double scale) {
        LinkRig rig(net::RenderingMode::kLocal,
                    ScriptedPath({0.0, 0.3, 0.5}, {Vec3(0.0, 0.0, 0.015), Vec3(0.0, 0.0, 0.015), Vec3(0.0, 0.0, 0.003)}));
        net::ContactMsg contact;
        contact.stiffness_n_per_m = 700.0;
        contact.point_count = 1;
        contact.point_local_m[0] = Vec3(0.0, 0.0, -0.002);
        press_wall(rig, contact, 900, [&](int i) {
            if (i == 100) rig.client->observe_tool_scale(scale);  // as the loop does when [ or ] resizes the tool
        });
        return rig.device.last_force_n().z;
    };
    EXPECT_NEAR(final_force_z(1.0), 0.0, 1e-9) << "the tool as configured does not reach the wall";
    EXPECT_GT(final_force_z(2.0), 0.2) << "the resized tool presses into the wall";
}

TEST(LinkWire, ContactPointsRoundTripAndTooManyAreRefused) {
    net::ContactMsg m;
    m.point_count = 3;
    m.point_radius_m = 0.002;
    for (int i = 0; i < 3; ++i) {
        m.point_local_m[i] = Vec3(0.001 * i, -0.002, 0.003);
        m.point_normal[i] = Vec3(0.0, 0.0, 1.0);
    }
    net::Header h;
    std::vector<std::uint8_t> d;
    net::encode(h, m, d);
    net::Header hh;
    ASSERT_EQ(net::decode_header(d.data(), d.size(), hh), net::DropReason::kNone);
    net::ContactMsg back;
    ASSERT_EQ(net::decode(d.data(), d.size(), back), net::DropReason::kNone);
    EXPECT_EQ(back.point_count, 3);
    EXPECT_EQ(back.point_radius_m, 0.002);
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(back.point_local_m[i], m.point_local_m[i]);
        EXPECT_EQ(back.point_normal[i], m.point_normal[i]);
    }
    d.pop_back();  // torn
    EXPECT_EQ(net::decode(d.data(), d.size(), back), net::DropReason::kBadLength);
    m.point_count = 0;  // no points: the single god-object, the shortest message
    net::encode(h, m, d);
    const std::size_t shortest = d.size();
    ASSERT_EQ(net::decode(d.data(), d.size(), back), net::DropReason::kNone);
    EXPECT_EQ(back.point_count, 0);
    // A count byte above the limit (the count sits 9 bytes before the end of a point-less message).
    d[shortest - 9] = static_cast<std::uint8_t>(net::kMaxContactPoints + 1);
    EXPECT_EQ(net::decode(d.data(), d.size(), back), net::DropReason::kOutOfRange);
}

TEST(LinkWire, StateWithAToolSampleRoundTripsAndBadFlagsAreRefused) {
    net::StateMsg m;
    m.state.t_s = 1.5;
    m.state.buttons = 3;
    m.has_tool = true;
    m.tool.tool_world.position = Vec3(0.01, -0.02, 0.3);
    m.tool.proxy_m = Vec3(0.01, -0.02, 0.301);
    m.tool.force_n = Vec3(0.0, 0.0, 0.7);
    m.tool.contact = true;
    m.tool.hold = false;
    std::vector<std::uint8_t> d;
    net::encode(net::Header{}, m, d);
    net::Header h;
    ASSERT_EQ(net::decode_header(d.data(), d.size(), h), net::DropReason::kNone);
    net::StateMsg back;
    ASSERT_EQ(net::decode(d.data(), d.size(), back), net::DropReason::kNone);
    EXPECT_TRUE(back.has_tool);
    EXPECT_EQ(back.tool.proxy_m, m.tool.proxy_m);
    EXPECT_EQ(back.tool.tool_world.position, m.tool.tool_world.position);
    EXPECT_TRUE(back.tool.contact);
    EXPECT_FALSE(back.tool.hold);
    EXPECT_EQ(back.state.buttons, 3u);
    // Without the tool the datagram is shorter, and a contact bit without a tool is refused.
    m.has_tool = false;
    std::vector<std::uint8_t> plain;
    net::encode(net::Header{}, m, plain);
    EXPECT_LT(plain.size(), d.size());
    const std::size_t flags_at = net::kHeaderBytes + 8 + 24 + 32 + 24 + 4 + 24;
    plain[flags_at] = 4;
    EXPECT_EQ(net::decode(plain.data(), plain.size(), back), net::DropReason::kOutOfRange);
    // A tool bit on a datagram without the tool's bytes is a length error.
    plain[flags_at] = 2;
    EXPECT_EQ(net::decode(plain.data(), plain.size(), back), net::DropReason::kBadLength);
}

TEST(SurfaceCodec, RoundTripAndRefusals) {
    auto wall = test::make_surface(1e-3, Vec3(-0.016, -0.016, -0.020));
    test::fill_set(*wall, 2, 0, 0, [](int u, int) { return test::Intervals{{0.0f, 20.0f + 0.1f * u}}; });
    wall->sets[2].material[5 * ActiveSurface::kMaxIntervals] = 3;
    std::vector<std::uint8_t> d;
    net::encode_surface({}, *wall, d);
    EXPECT_LT(d.size(), 20000u);
    auto back = std::make_unique<ActiveSurface>();
    ASSERT_EQ(net::decode_surface(d.data(), d.size(), *back), net::DropReason::kNone);
    EXPECT_EQ(back->sequence, wall->sequence);
    EXPECT_EQ(back->sets[2].nu, ActiveSurface::kWindow);
    EXPECT_EQ(back->sets[2].exit(7, 3, 0), wall->sets[2].exit(7, 3, 0));
    EXPECT_EQ(back->sets[2].material_of(5, 0, 0), 3);
    EXPECT_EQ(back->sets[0].nu, 0);
    std::vector<std::uint8_t> torn(d.begin(), d.end() - 1);
    EXPECT_EQ(net::decode_surface(torn.data(), torn.size(), *back), net::DropReason::kBadLength);
    wall->sets[1].nu = ActiveSurface::kWindow + 1;
    net::encode_surface({}, *wall, d);
    EXPECT_EQ(net::decode_surface(d.data(), d.size(), *back), net::DropReason::kOutOfRange);
}

}  // namespace
}  // namespace tridex::haptics

namespace tridex::haptics {
namespace {

TEST(DeviceServer, SessionThatLoadsForSecondsIsServedWhenItsLoopStarts) {
    LinkRig rig(net::RenderingMode::kDistributed, ScriptedPath::hold(Vec3(0.0)));
    ASSERT_TRUE(rig.connect());
    const std::size_t steps = rig.device.steps();
    for (int i = 0; i < 2000; ++i) rig.server_tick();  // the session loads its workpiece; the device rests
    EXPECT_LE(rig.device.steps(), steps + 11);  // until the watchdog's 9 ms of silence
    rig.client->bring_up();
    devices::DeviceState s;
    for (int i = 0; i < 50; ++i) {
        ASSERT_TRUE(rig.client->read(s));
        rig.client->write(Vec3(0.0, 0.0, 0.25), Vec3(0.0));
        rig.server_tick();
    }
    EXPECT_FALSE(rig.client->link_down());
    EXPECT_NEAR(rig.device.last_force_n().z, 0.25, 1e-12);
    EXPECT_EQ(rig.client->link_stats().link_outages, 0u);
}

}  // namespace
}  // namespace tridex::haptics
