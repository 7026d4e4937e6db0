// A wall session with the hands alone: offscreen `tridex run --head dtrack:PORT:0 --device flystick:PORT:1`, driven
// only by DTrack datagrams sent over UDP as the wall's tracker sends them (the head, and a Flystick that is the tool,
// with its buttons), no key event. Through the pie menu and the Flystick's bound buttons the person changes the
// operation (a two-stroke mark: Operation, then Union), carves, undoes (button 2), redoes and saves (the menu), and
// ends the session (End, then End session); report.json counts each step and the saved model holds the redone cut.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "../devices/dtrack_sender.hpp"
#include "app/session/run_options.hpp"
#include "app/session/run_session.hpp"
#include "devices/tracking/dtrack_receiver.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

using tridex::test::DTrackSender;
using tridex::test::dtrack_flystick_datagram;

// Where the Flystick is and which of its DTrack buttons are held (bit 0 trigger, bit i button i) at time t (s) of
// the script; positions in mm, tracker frame (the display's world: identity tracker_to_wall).
struct Hand {
    Vec3 mm;
    unsigned buttons;
};

Hand script_at(double t) {
    const Vec3 a(0.0, 120.0, 50.0);  // above the workpiece, facing the head
    constexpr unsigned kTrigger = 1u, kMenu = 1u << 1, kUndo = 1u << 2;
    const double t0 = 3.0;  // the session is up and the tool acquired before this
    const double s = t - t0;
    if (s < 0.0) return {a, 0};
    if (s < 0.6) return {a, kMenu};                                   // the menu opens at the hand
    if (s < 0.9) return {a + Vec3(0.0, 62.0, 0.0), kMenu};            // up past the ring: Operation opens there
    if (s < 1.3) return {a + Vec3(26.0, 77.0, 0.0), kMenu};           // then toward 2 o'clock: Union
    if (s < 1.7) return {Vec3(-40.0, 62.0, 50.0), 0};                 // released: chosen; to the carve's start
    if (s < 2.7) return {Vec3(-40.0 + 80.0 * (s - 1.7), 62.0, 50.0), kTrigger};  // a ridge along the top
    if (s < 3.1) return {a, 0};
    if (s < 3.3) return {a, kUndo};                                   // button 2: undo
    if (s < 3.6) return {a, 0};
    if (s < 4.1) return {a + Vec3(30.0, 0.0, 0.0), kMenu};            // the menu at 3 o'clock: Redo
    if (s < 4.4) return {a + Vec3(30.0, 0.0, 0.0), 0};
    if (s < 4.7) return {a, 0};
    if (s < 5.2) return {a + Vec3(21.0, -21.0, 0.0), kMenu};          // the menu at half past four: Save
    if (s < 5.5) return {a + Vec3(21.0, -21.0, 0.0), 0};
    if (s < 5.8) return {a, 0};
    if (s < 6.2) return {a, kMenu};                                   // the menu again
    if (s < 6.6) return {a + Vec3(0.0, -62.0, 0.0), kMenu};           // down past the ring: End opens there
    if (s < 7.0) return {a + Vec3(0.0, -35.0, 0.0), kMenu};           // back up in End's ring: End session
    return {a + Vec3(0.0, -35.0, 0.0), 0};                            // released: the session ends
}

TEST(WallMenu, TheHandsAloneChangeTheOperationCarveUndoRedoSaveAndEnd) {
    namespace fs = std::filesystem;
    const fs::path dir = test::temp_dir("wall_menu");
    const std::string scene = (dir / "scene.json").string();
    std::ofstream(scene) << R"({
  "workpiece": { "resolution": 32, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "display": { "preset": "desktop", "resolution": [96, 72], "refresh_hz": 60 }
})";
    int port = 0;
    {
        devices::DTrackReceiver probe(0, "127.0.0.1");
        port = probe.port();
    }
    RunOptions o;
    o.scene = scene;
    o.display = "offscreen";
    o.stereo = "side-by-side";
    o.seconds = 20.0;  // a safety net: the menu's End session ends it near 10 s
    o.out = (dir / "out").string();
    o.save = (dir / "model.tdx").string();
    o.head = "dtrack:" + std::to_string(port) + ":0";
    o.device = "flystick:" + std::to_string(port) + ":1";
    std::atomic<bool> stop{false};
    std::thread sender([&] {
        DTrackSender tx(port);
        const auto t_start = std::chrono::steady_clock::now();
        for (unsigned fr = 1; !stop.load(); ++fr) {
            const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
            const Hand h = script_at(t);
            tx.send(tridex::test::dtrack_datagram(fr, 0, Vec3(0.0, 0.0, 600.0), glm::dmat3(1.0)));
            tx.send(dtrack_flystick_datagram(fr, 1, h.mm, glm::dmat3(1.0), h.buttons, 0.0, 0.0));
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    });
    try {
        run_stereo_session(o);
    } catch (...) {
        stop = true;
        sender.join();
        throw;
    }
    stop = true;
    sender.join();
    const nlohmann::json rep = nlohmann::json::parse(std::ifstream(dir / "out" / "report.json"));
    const nlohmann::json& c = rep.at("controls");
    std::printf("[wall menu] controls %s\n", c.dump().c_str());
    EXPECT_EQ(rep.at("notes")[0], "ended: the session was ended (session.end)") << rep.at("notes").dump();
    EXPECT_EQ(c.at("menu").at("choices").at("op.union"), 1) << c.dump();
    EXPECT_EQ(c.at("menu").at("choices").at("edit.redo"), 1) << c.dump();
    EXPECT_EQ(c.at("menu").at("choices").at("file.save"), 1) << c.dump();
    EXPECT_EQ(c.at("menu").at("choices").at("session.end"), 1) << c.dump();
    EXPECT_EQ(c.at("menu").at("opens"), 4) << c.dump();
    EXPECT_EQ(c.at("actions").at("edit.undo").at("button"), 1) << c.dump();
    EXPECT_EQ(c.at("bindings").at("tool").at("buttons").at("button1"), "menu");
    EXPECT_EQ(rep.at("history").at("undos"), 1) << rep.at("history").dump();
    EXPECT_EQ(rep.at("history").at("redos"), 1) << rep.at("history").dump();
    EXPECT_GE(rep.at("saves").at("count").get<int>(), 1);
    EXPECT_TRUE(fs::exists(dir / "model.tdx"));
    // The union's ridge, undone and redone, is in the model.
    EXPECT_GT(rep.at("volume_after_m3").get<double>(), rep.at("volume_before_m3").get<double>());
}

}  // namespace
}  // namespace tridex::app
