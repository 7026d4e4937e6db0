// tests/haptics/test_local_rendering_stale.cpp - stale forces in local haptic rendering over the link shim
// (simulated clock), logged as stale on both ends: when the server's states stop coming, the session's loop logs the
// server's last force as stale on every tick that brought no new tool sample, counts those ticks and carves nothing
// with them (fresh again once states come); when the tool leaves the region of the newest snapshot, the server
// counts and logs the forces it renders there as stale.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "core/spsc_ring.hpp"
#include "core/triple_buffer.hpp"
#include "haptics/haptic_loop.hpp"
#include "link_rig.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

namespace net = devices::net;
using devices::ScriptedPath;
using test::LinkRig;

TEST(LocalRendering, AStalledLinkLogsTheLastForceAsStale) {
    // The hand presses 3 mm into a z = 0 wall; the server's god-object pushes back.
    LinkRig rig(net::RenderingMode::kLocal, ScriptedPath({0.0, 0.2}, {Vec3(0.0, 0.0, 0.010), Vec3(0.0, 0.0, -0.003)}));
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
    TripleBuffer<ActiveSurface> session_surface;  // never published: every force comes from the server
    SpscRing<ToolSample> samples(4096);
    HapticLoop loop(*rig.client, session_surface, samples, cfg);
    // One tick of the session; `serve` false: the server does not tick (its states stop coming), the clock goes on.
    struct Tick {
        TickRecord rec;
        int carving = 0;  // tool samples pushed with an operation
    };
    const auto tick = [&](bool serve) {
        Tick t;
        rig.client->observe_surface(*wall);
        t.rec = loop.step(rig.now);
        rig.client->service();
        if (serve) {
            rig.server_tick();
        } else {
            rig.now += 1e-3;
        }
        ToolSample s;
        while (samples.try_pop(s)) t.carving += s.op != ToolOp::kNone ? 1 : 0;
        return t;
    };
    std::vector<Tick> before, stalled, after;
    for (int i = 0; i < 500; ++i) before.push_back(tick(true));
    for (int i = 0; i < 30; ++i) stalled.push_back(tick(false));
    for (int i = 0; i < 300; ++i) after.push_back(tick(true));
    loop.stop();

    // Served: each tick has the server's tool sample of its own, the wall's force, and carves.
    for (std::size_t i = 400; i < before.size(); ++i) EXPECT_FALSE(before[i].rec.remote_stale) << "served tick " << i;
    EXPECT_GT(before.back().rec.force_n.z, 0.3);
    EXPECT_GT(before.back().carving, 0);
    // Stalled: the same earlier force on every tick, logged as stale, and no carving with it.
    for (std::size_t i = 1; i < stalled.size(); ++i) {
        EXPECT_TRUE(stalled[i].rec.remote_stale) << "stalled tick " << i;
        EXPECT_EQ(stalled[i].carving, 0) << "stalled tick " << i;
    }
    // Served again: fresh once more.
    for (std::size_t i = 100; i < after.size(); ++i) EXPECT_FALSE(after[i].rec.remote_stale) << "served again " << i;
    EXPECT_GT(after.back().carving, 0);
    const std::size_t stale_ticks = loop.stats().stale_remote_ticks;
    EXPECT_GE(stale_ticks, stalled.size() - 1);
    EXPECT_LE(stale_ticks, stalled.size() + 5);  // the first ticks of a stall and of the recovery only
    EXPECT_EQ(rig.client->link_stats().stale_tool_samples, stale_ticks);
}

// The hand presses 3 mm into a z = 0 wall at the snapshot's centre, then slides 40 mm sideways along it, past the
// 14.5 mm the snapshot covers on each side (kCoverRays rays of 1 mm); no newer snapshot comes.
TEST(LocalRendering, TheServerLogsForcesOnASnapshotTheToolLeftAsStale) {
    LinkRig rig(net::RenderingMode::kLocal,
                ScriptedPath({0.0, 0.2, 0.4, 0.8}, {Vec3(0.0, 0.0, 0.010), Vec3(0.0, 0.0, -0.003),
                                                    Vec3(0.0, 0.0, -0.003), Vec3(0.040, 0.0, -0.003)}));
    net::ContactMsg contact;
    contact.stiffness_n_per_m = 700.0;
    contact.tool_radius_m = 0.0;
    rig.client->set_contact(contact);
    ASSERT_TRUE(rig.connect());
    rig.client->bring_up();
    auto wall = test::make_surface(1e-3, Vec3(-0.032, -0.032, -0.020));
    test::fill_set(*wall, 2, 0, 0, [](int, int) { return test::Intervals{{0.0f, 20.0f}}; });
    wall->centre_m = Vec3(0.0);
    devices::DeviceState s;
    std::uint64_t stale_at_400 = 0;
    for (int i = 0; i < 1000; ++i) {
        ASSERT_TRUE(rig.client->read(s));
        rig.client->observe_surface(*wall);  // the same snapshot every time: sent once
        rig.client->write(Vec3(0.0), Vec3(0.0));
        rig.client->service();
        rig.server_tick();
        if (i == 400) stale_at_400 = rig.server->stats().stale_force_ticks;
    }
    const DeviceServerStats st = rig.server->stats();
    std::printf("[local rendering] %llu of 1000 server ticks rendered on a snapshot the tool had left; the grip at x = "
                "%.1f mm\n", static_cast<unsigned long long>(st.stale_force_ticks), 1e3 * rig.device.position_m().x);
    EXPECT_GT(rig.device.position_m().x, 0.030);
    EXPECT_EQ(st.snapshots, 1u);
    EXPECT_EQ(st.stale_snapshots, 0u) << "the snapshot covered the tool when it arrived";
    EXPECT_EQ(stale_at_400, 0u) << "forces inside the snapshot's region are not stale";
    EXPECT_GT(st.stale_force_ticks, 100u) << "the slide past the region rendered no stale force";
    const auto logged = std::count_if(rig.server_events.begin(), rig.server_events.end(),
                                      [](const std::string& e) { return e.find("forces are stale") != std::string::npos; });
    EXPECT_EQ(logged, 1) << "one event when it began";
}

}  // namespace
}  // namespace tridex::haptics
