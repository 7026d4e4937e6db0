// A wall session with the hands alone: offscreen `tridex run --head dtrack:PORT:0 --device flystick:PORT:1`, driven
// only by DTrack datagrams sent over UDP as the wall's tracker sends them (the head, and a Flystick that is the tool,
// with its buttons), no key event. Through the pie menu and the Flystick's bound buttons the person changes the
// operation (a two-stroke mark: Operation, then Union), carves, undoes (button 2), redoes and saves (the menu), and
// ends the session (End, then End session), its joystick growing the tool on the way; report.json counts each step
// and the saved model holds the redone cut.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "../devices/dtrack_sender.hpp"
#include "app/commands/replay/replay.hpp"
#include "app/menu/menu_frame.hpp"
#include "app/session/run/run_options.hpp"
#include "app/session/run/run_session.hpp"
#include "devices/recording.hpp"
#include "devices/tracking/dtrack_receiver.hpp"
#include "dtrack_session.hpp"
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
    double joystick_y = 0.0;
};

// `ready_s`: seconds since the session was ready (negative before).
Hand script_at(double ready_s) {
    const Vec3 a(0.0, 120.0, 50.0);  // above the workpiece, facing the head
    constexpr unsigned kTrigger = 1u, kMenu = 1u << 1, kUndo = 1u << 2;
    if (ready_s < 0.0) return {a, 0};
    // From a second after the session was ready (the tool acquired), each step held 1.5 times the times below, so
    // that even a loaded machine draws several frames of each.
    const double s = (ready_s - 1.0) / 1.5;
    if (s < 0.0) return {a, 0};
    if (s < 0.6) return {a, kMenu};                                   // the menu opens at the hand
    if (s < 0.9) return {a + Vec3(0.0, 62.0, 0.0), kMenu};            // up past the ring: Operation opens there
    if (s < 1.3) return {a + Vec3(26.0, 77.0, 0.0), kMenu};           // then toward 2 o'clock: Union
    if (s < 1.45) return {a + Vec3(26.0, 77.0, 0.0), 0};              // released there: chosen
    if (s < 1.7) return {Vec3(-40.0, 62.0, 50.0), 0};                 // to the carve's start
    if (s < 2.7) return {Vec3(-40.0 + 80.0 * (s - 1.7), 62.0, 50.0), kTrigger};  // a ridge along the top
    if (s < 3.1) return {a, 0};
    if (s < 3.3) return {a, kUndo};                                   // button 2: undo
    if (s < 3.6) return {a, 0};
    if (s < 3.75) return {a, kMenu};                                  // the menu opens at the hand, held still
    if (s < 4.1) return {a + Vec3(30.0, 0.0, 0.0), kMenu};            // then to 3 o'clock: Redo
    if (s < 4.4) return {a + Vec3(30.0, 0.0, 0.0), 0};
    if (s < 4.7) return {a, 0};
    if (s < 4.85) return {a, kMenu};                                  // the menu opens at the hand, held still
    if (s < 5.2) return {a + Vec3(21.0, -21.0, 0.0), kMenu};          // then to half past four: Save
    if (s < 5.5) return {a + Vec3(21.0, -21.0, 0.0), 0};
    if (s < 5.8) return {a, 0, 0.9};                                  // the joystick forward: the tool grows
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
    const int port = test::free_dtrack_port();
    RunOptions o;
    o.scene = scene;
    o.display = "offscreen";
    o.stereo = "side-by-side";
    o.seconds = 30.0;  // a safety net: the menu's End session ends it near 14 s
    o.out = (dir / "out").string();
    o.save = (dir / "model.tdx").string();
    o.record = (dir / "wall.trdx").string();
    o.head = "dtrack:" + std::to_string(port) + ":0";
    o.device = "flystick:" + std::to_string(port) + ":1";
    fs::remove_all(dir / "out");  // the journal appearing is the session's start
    test::SessionReady ready(dir / "out" / "session.tdj");
    test::run_while_sending(o, port, [&ready](DTrackSender& tx, unsigned fr, double t) {
        const Hand h = script_at(ready.since(t));
        tx.send(tridex::test::dtrack_datagram(fr, 0, Vec3(0.0, 0.0, 600.0), glm::dmat3(1.0)));
        tx.send(dtrack_flystick_datagram(fr, 1, h.mm, glm::dmat3(1.0), h.buttons, 0.0, h.joystick_y));
    });
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
    EXPECT_GE(c.at("actions").at("tool.scale").at("axis"), 1) << c.dump();  // the Flystick's joystick
    EXPECT_EQ(c.at("bindings").at("tool").at("joystick_y"), "tool.scale");
    EXPECT_EQ(c.at("bindings").at("tool").at("buttons").at("button1"), "menu");
    EXPECT_EQ(rep.at("history").at("undos"), 1) << rep.at("history").dump();
    EXPECT_EQ(rep.at("history").at("redos"), 1) << rep.at("history").dump();
    EXPECT_GE(rep.at("saves").at("count").get<int>(), 1);
    EXPECT_TRUE(fs::exists(dir / "model.tdx"));
    // The journal, written as the session ran, is among the files the report lists.
    bool journal_listed = false;
    for (const nlohmann::json& f : rep.at("files")) journal_listed = journal_listed || f.get<std::string>().ends_with("session.tdj");
    EXPECT_TRUE(journal_listed) << rep.at("files").dump();
    // The union's ridge, undone and redone, is in the model.
    EXPECT_GT(rep.at("volume_after_m3").get<double>(), rep.at("volume_before_m3").get<double>());

    // The recording keeps the menu's track: four times shown, the Operation ring with Union lit among them.
    const devices::Recording rec = devices::read_recording(o.record);
    const MenuTrack track = MenuTrack::from_json_text(rec.header.menu, o.record);
    ASSERT_GT(track.size(), 4u);
    int opened = 0;
    bool union_lit = false;
    MenuFrame prev;
    for (double t = 0.0; t < 30.0; t += 0.005) {
        const MenuFrame f = track.at(t);
        if (f.shown && !prev.shown) ++opened;
        union_lit = union_lit || (f.path == std::vector<std::uint8_t>{0} && f.highlighted == 1);
        prev = f;
    }
    EXPECT_EQ(opened, 4);
    EXPECT_TRUE(union_lit);
    // The replay sculpts the same model (no carving while the menu was open) and draws the menu in its film strip
    // where the session showed it.
    OutputOptions out;
    out.out = (dir / "replay").string();
    out.width = 64;
    out.height = 48;
    StripRequest strip;
    strip.path = (dir / "strip.png").string();
    strip.options.frames = 24;
    strip.options.width = 96;
    strip.options.height = 72;
    testing::internal::CaptureStdout();
    run_replay(o.record, out, SculptOptions{true, false, false, false, ""}, "", strip);
    const std::string said = testing::internal::GetCapturedStdout();
    const nlohmann::json rep2 = nlohmann::json::parse(std::ifstream(dir / "replay" / "report.json"));
    EXPECT_EQ(rep2.at("volume_after_m3").get<double>(), rep.at("volume_after_m3").get<double>());
    const std::size_t at = said.find("pictures (");
    ASSERT_NE(at, std::string::npos) << said;
    const int with_menu = std::atoi(said.c_str() + at + 10);
    std::printf("[wall menu] replay: %s", said.substr(said.find("film strip")).c_str());
    EXPECT_GE(with_menu, 2) << said;  // the Redo menu, held half a second before the redo, about 3 pictures
}

// The wand's menu and joystick with a haptic device carving: `--wand dtrack:PORT:1` (a Flystick navigating) and the
// scene's scripted hand on the emulated Falcon (its stroke delayed 7 s). Before the stroke the wand's button 1 opens
// the menu at the wand and a two-stroke mark chooses Operation, then Union, so the stroke adds material instead of
// carving; the joystick pushed forward scales the scene. The menu opened by the wand is not felt (the wand renders
// no force), and the Falcon keeps carving only outside the menu.
TEST(WallMenu, TheWandsMenuChangesTheHapticDevicesOperationAndItsJoystickScales) {
    namespace fs = std::filesystem;
    const fs::path dir = test::temp_dir("wall_wand_menu");
    const std::string scene = (dir / "scene.json").string();
    std::ofstream(scene) << R"({
  "workpiece": { "resolution": 32, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "device": { "driver": "falcon-emulator" },
  "stroke": { "duration_s": 1.0, "length_m": 0.04, "depth_m": 0.003, "press_axis": "z", "start_s": 7.0 },
  "display": { "preset": "desktop", "resolution": [96, 72], "refresh_hz": 60 }
})";
    const int port = test::free_dtrack_port();
    RunOptions o;
    o.scene = scene;
    o.display = "offscreen";
    o.stereo = "side-by-side";
    o.out = (dir / "out").string();
    o.head = "dtrack:" + std::to_string(port) + ":0";
    o.wand = "dtrack:" + std::to_string(port) + ":1";
    fs::remove_all(dir / "out");  // the journal appearing is the session's start
    test::SessionReady ready(dir / "out" / "session.tdj");
    test::run_while_sending(o, port, [&ready](DTrackSender& tx, unsigned fr, double t) {  // ends with the stroke
        const Vec3 a(0.0, 0.0, 300.0);  // the wand, tracker mm: level with the head, so the ring faces it square
        const double since = ready.since(t);
        const double s = since < 0.0 ? -1.0 : (since - 1.0) / 1.5;  // from 1 s after ready, each step held 1.5 times
        Vec3 at = a;
        unsigned buttons = 0;
        double joy = 0.0;
        if (s >= 0.0 && s < 1.3) buttons = 1u << 1;             // button 1: the menu at the wand
        if (s >= 0.5 && s < 0.8) at = a + Vec3(0.0, 62.0, 0.0);  // up past the ring: Operation
        if (s >= 0.8 && s < 1.5) at = a + Vec3(26.0, 77.0, 0.0); // toward 2 o'clock: Union; released
        if (s >= 1.6 && s < 2.1) joy = 0.8;                     // the joystick forward: larger
        tx.send(tridex::test::dtrack_datagram(fr, 0, Vec3(0.0, 0.0, 600.0), glm::dmat3(1.0)));
        tx.send(dtrack_flystick_datagram(fr, 1, at, glm::dmat3(1.0), buttons, 0.0, joy));
    });
    const nlohmann::json rep = nlohmann::json::parse(std::ifstream(dir / "out" / "report.json"));
    const nlohmann::json& c = rep.at("controls");
    std::printf("[wall wand menu] controls %s\n[wall wand menu] wand %s\n", c.at("menu").dump().c_str(),
                rep.at("wand").dump().c_str());
    EXPECT_EQ(c.at("menu").at("choices").at("op.union"), 1) << c.dump();
    EXPECT_EQ(c.at("bindings").at("wand").at("buttons").at("button1"), "menu");
    EXPECT_GT(rep.at("wand").at("scaled_by").get<double>(), 1.05) << rep.at("wand").dump();
    EXPECT_EQ(rep.at("haptics").at("device_driver").get<std::string>(), "falcon-emulator");
    // The stroke added material: the operation the wand's menu chose.
    EXPECT_GT(rep.at("volume_after_m3").get<double>(), rep.at("volume_before_m3").get<double>());
}

}  // namespace
}  // namespace tridex::app
