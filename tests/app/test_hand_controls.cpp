// The hands' controls without a session: the one list of actions, the desk's keys as action names, bindings from the
// drivers' capabilities and from a file (with its errors), button edges, the pie menu's choices (held, flicked,
// marked through a sub-ring, clicked) and its meshes at the hand's depth.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/actions/action_registry.hpp"
#include "app/actions/bindings.hpp"
#include "app/input/key_bindings.hpp"
#include "app/menu/menu_frame.hpp"
#include "app/menu/pie_menu.hpp"
#include "app/menu/pie_menu_mesh.hpp"
#include "app/scene/session_spec.hpp"
#include "app/session/run/run_actions.hpp"
#include "core/error.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

// Records what the actions asked for.
struct Recorder final : ActionTarget {
    ToolOp op_now = ToolOp::kSubtract;
    int size = 0;
    std::vector<std::string> did;
    void set_op(ToolOp o) override {
        op_now = o;
        did.push_back(std::string("op ") + tool_op_name(o));
    }
    ToolOp op() const override { return op_now; }
    std::uint8_t material_now = 1;
    void set_material(std::uint8_t id) override {
        material_now = id;
        did.push_back("material " + std::to_string(id));
    }
    std::uint8_t material() const override { return material_now; }
    bool resize_tool(int steps) override {
        size += steps;
        did.push_back("size " + std::to_string(steps));
        return true;
    }
    bool request(SculptRequest r) override {
        did.push_back(r == SculptRequest::kUndo ? "undo" : r == SculptRequest::kRedo ? "redo" : "save");
        return true;
    }
    void reset_scene() override { did.push_back("reset"); }
    void swap_eyes() override { did.push_back("swap"); }
    void toggle_occlusion() override { did.push_back("ao"); }
    void toggle_symmetry() override { did.push_back("symmetry"); }
    void next_workpiece() override { did.push_back("workpiece"); }
    void end_session() override { did.push_back("end"); }
};

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(Actions, OneListNamesEveryKeyAndEveryMenuSlice) {
    const ActionRegistry& reg = builtin_actions();
    std::set<std::string> names;
    for (const Action& a : reg.all()) {
        EXPECT_TRUE(names.insert(a.name).second) << a.name;
        EXPECT_FALSE(a.label.empty()) << a.name;
        if (a.kind == ActionKind::kCommand) {
            EXPECT_TRUE(a.run) << a.name;
        }
    }
    // Every desk key names a command of the registry.
    for (const KeyBinding& k : desk_key_bindings()) {
        const Action* a = reg.find(k.action);
        ASSERT_NE(a, nullptr) << chord_name(k);
        EXPECT_EQ(a->kind, ActionKind::kCommand) << chord_name(k);
    }
    // Every leaf of the default menu is a command, and every command a key has is in the menu.
    std::set<std::string> in_menu;
    std::function<void(const MenuItem&)> walk = [&](const MenuItem& m) {
        if (!m.action.empty()) {
            EXPECT_EQ(reg.get(m.action, "menu").kind, ActionKind::kCommand);
            in_menu.insert(m.action);
        }
        for (const MenuItem& c : m.children) walk(c);
    };
    const MenuItem root = default_menu();
    walk(root);
    for (const KeyBinding& k : desk_key_bindings()) EXPECT_TRUE(in_menu.count(k.action)) << k.action;
    EXPECT_EQ(root.children.size(), 8u);
    // Running them.
    Recorder r;
    for (const char* a : {"op.union", "op.next", "tool.larger", "edit.undo", "edit.redo", "file.save", "view.reset",
                          "view.swap_eyes", "view.occlusion", "session.end"})
        EXPECT_TRUE(reg.run(a, r)) << a;
    EXPECT_EQ(r.did, (std::vector<std::string>{"op union", "op paint", "size 1", "undo", "redo", "save", "reset",
                                               "swap", "ao", "end"}));
    EXPECT_FALSE(reg.run("menu", r));  // held: the input reads it
    EXPECT_FALSE(reg.run("no.such", r));
    const std::string e = error_of([&] { (void)reg.get("edit.undoo", "bindings.tool.buttons.button1"); });
    EXPECT_NE(e.find("bindings.tool.buttons.button1: unknown action 'edit.undoo' (did you mean 'edit.undo'?)"),
              std::string::npos) << e;
    EXPECT_EQ(next_op(ToolOp::kPull), ToolOp::kGrab);
    EXPECT_EQ(next_op(ToolOp::kGrab), ToolOp::kSubtract);
    Recorder g;
    EXPECT_TRUE(reg.run("op.grab", g));
    EXPECT_EQ(g.did, (std::vector<std::string>{"op grab"}));
    EXPECT_EQ(next_op(ToolOp::kPaint), ToolOp::kPush);
}

TEST(Actions, DeskKeysMatchTheirChords) {
    using renderer::Key;
    namespace mod = renderer::modifier;
    ASSERT_NE(find_key_binding(Key::kZ, mod::kControl, false), nullptr);
    EXPECT_EQ(find_key_binding(Key::kZ, mod::kControl, false)->action, "edit.undo");
    EXPECT_EQ(find_key_binding(Key::kZ, mod::kControl | mod::kShift, false)->action, "edit.redo");
    EXPECT_EQ(find_key_binding(Key::k4, 0, false), nullptr);  // digits are the stylus's
    EXPECT_EQ(find_key_binding(Key::k4, 0, true)->action, "op.push");
    EXPECT_EQ(find_key_binding(Key::k7, 0, true)->action, "op.grab");
    EXPECT_EQ(find_key_binding(Key::kZ, 0, true), nullptr);
    EXPECT_EQ(chord_name(*find_key_binding(Key::kZ, mod::kControl | mod::kShift, false)), "Ctrl+Shift+Z");
}

TEST(Bindings, DefaultsFollowTheDriversCapabilities) {
    const Bindings fly = default_bindings("flystick", driver_caps("flystick"));
    EXPECT_EQ(fly.tool.action_of(1), "engage");  // the trigger
    EXPECT_EQ(fly.tool.action_of(2), "menu");    // button 1
    EXPECT_EQ(fly.wand.action_of(0), "nav.grab");
    EXPECT_EQ(fly.wand.action_of(1), "menu");
    EXPECT_EQ(fly.wand.joystick_y, "nav.scale");
    const Bindings falcon = default_bindings("falcon", driver_caps("falcon"));
    EXPECT_EQ(falcon.tool.action_of(1), "menu");
    EXPECT_EQ(falcon.tool.action_of(2), "edit.undo");
    const nlohmann::json j = bindings_json(fly);
    EXPECT_EQ(j.at("tool").at("buttons").at("button1"), "menu");
    EXPECT_EQ(j.at("wand").at("joystick_y"), "nav.scale");
}

TEST(Bindings, AFileRebindsAndNamesWhatIsWrong) {
    Bindings b = default_bindings("flystick", driver_caps("flystick"));
    apply_bindings(nlohmann::json::parse(R"({"tool": {"buttons": {"button2": "op.next", "button1": "none"}},
                                              "wand": {"buttons": {"button2": "menu"}, "joystick_y": "tool.scale"}})"),
                   "my.json", b);
    EXPECT_EQ(b.tool.action_of(3), "op.next");
    EXPECT_EQ(b.tool.action_of(2), "");
    EXPECT_EQ(b.wand.action_of(2), "menu");
    EXPECT_EQ(b.wand.joystick_y, "tool.scale");
    EXPECT_EQ(b.source, "my.json");
    const auto bad = [](const char* text) {
        Bindings d = default_bindings("flystick", driver_caps("flystick"));
        return error_of([&] { apply_bindings(nlohmann::json::parse(text), "wall.json", d); });
    };
    EXPECT_NE(bad(R"({"tool": {"buttons": {"button9": "menu"}}})").find(
                  "wall.json: bindings.tool.buttons.button9: the flystick driver has no button 'button9'; its buttons: "
                  "trigger, button1"),
              std::string::npos);
    EXPECT_NE(bad(R"({"tool": {"buttons": {"button1": "edit.und"}}})").find("did you mean 'edit.undo'"),
              std::string::npos);
    EXPECT_NE(bad(R"({"tool": {"buttons": {"button1": "engage"}}})").find("'engage' goes on the button"),
              std::string::npos);
    EXPECT_NE(bad(R"({"tool": {"buttons": {"button1": "nav.scale"}}})").find("driven by an axis"), std::string::npos);
    EXPECT_NE(bad(R"({"wand": {"joystick_y": "edit.undo"}})").find("not driven by an axis"), std::string::npos);
    EXPECT_NE(bad(R"({"tool": {"buttons": {"button1": "nav.grab"}}})").find("the wand's"), std::string::npos);
    EXPECT_NE(bad(R"({"tool": {"joystick_y": "nav.scale"}})").find("'nav.scale' is the wand's"), std::string::npos);
    Bindings falcon = default_bindings("falcon", driver_caps("falcon"));
    EXPECT_NE(error_of([&] {
                  apply_bindings(nlohmann::json::parse(R"({"tool": {"joystick_y": "tool.scale"}})"), "f.json", falcon);
              }).find("f.json: bindings.tool.joystick_y: the falcon driver has no joystick"),
              std::string::npos);
    EXPECT_NE(bad(R"({"head": {}})").find("wall.json: bindings.head: unknown device; use tool or wand"),
              std::string::npos);
    EXPECT_NE(bad(R"({"tool": {"buttons": {"button1": 3}}})").find("must be an action name"), std::string::npos);
}

TEST(Bindings, AMalformedFileSaysLineAndColumn) {
    const std::filesystem::path dir = test::temp_dir("bindings_file");
    const std::string path = (dir / "b.json").string();
    std::ofstream(path) << "{\n  \"bindings\": {\n    \"tool\": {\"buttons\": {\"button1\": \"menu\"}\n  }\n";
    const std::string e = error_of([&] { (void)load_bindings(path, "flystick", driver_caps("flystick")); });
    EXPECT_NE(e.find(path + ": not valid JSON: parse error at line 5, column"), std::string::npos) << e;
    EXPECT_NE(e.find("expected"), std::string::npos) << e;
    std::ofstream(path) << R"({"bindings": {"tool": {"buttons": {"button1": 1e400}}}})";
    const std::string huge = error_of([&] { (void)load_bindings(path, "flystick", driver_caps("flystick")); });
    EXPECT_NE(huge.find(path + ": not valid JSON: number overflow at line 1, column 47, field 'bindings.tool.buttons.button1'"),
              std::string::npos)
        << huge;
    std::ofstream(path) << R"({"bindings": {"tool": {"buttons": {"button2": "edit.redo"}}}})";
    const Bindings b = load_bindings(path, "flystick", driver_caps("flystick"));
    EXPECT_EQ(b.tool.action_of(3), "edit.redo");
    EXPECT_NE(error_of([&] { (void)load_bindings((dir / "none.json").string(), "flystick", driver_caps("flystick")); })
                  .find("cannot read the bindings file"),
              std::string::npos);
}

TEST(Bindings, ReaderRunsEachPressOnceAndIgnoresButtonsHeldAtTheStart) {
    const Bindings b = default_bindings("flystick", driver_caps("flystick"));
    BindingReader r(b.tool);
    std::vector<std::string> got;
    r.update(1u << 3, got);  // held at the start: nothing
    r.update(1u << 3, got);
    EXPECT_TRUE(got.empty());
    r.update(0, got);
    r.update(1u << 3, got);  // button2: undo
    r.update(1u << 3, got);
    r.update((1u << 3) | (1u << 4), got);  // button3: redo
    EXPECT_EQ(got, (std::vector<std::string>{"edit.undo", "edit.redo"}));
    r.update(1u << 2, got);
    EXPECT_TRUE(r.held("menu"));
    EXPECT_EQ(got.size(), 2u);  // the menu is held, not a command
}

// A menu opened at the origin facing a head on +z: right is +x, up is +y.
struct MenuRig {
    MenuItem root = default_menu();
    PieMenu menu{PieMenuSettings{0.05, 0.012, 0.25}};
    const Vec3 head{0.0, 0.0, 0.6};
    Vec3 at(double clock_deg, double r) const {
        const double a = clock_deg * 3.14159265358979 / 180.0;
        return Vec3(r * std::sin(a), r * std::cos(a), 0.0);
    }
};

TEST(PieMenu, SlicesGoClockwiseFromTwelveAndAHeldReleaseChooses) {
    MenuRig m;
    m.menu.open(m.root, Vec3(0.0), m.head, 0.0);
    ASSERT_TRUE(m.menu.is_open());
    EXPECT_NEAR(m.menu.ring().right.x, 1.0, 1e-12);
    EXPECT_NEAR(m.menu.ring().up.y, 1.0, 1e-12);
    EXPECT_FALSE(m.menu.shown(0.1));
    EXPECT_TRUE(m.menu.shown(0.3));
    EXPECT_EQ(m.menu.slice_at(m.at(0.0, 0.005)), -1);  // the dead zone
    for (int k = 0; k < 8; ++k) EXPECT_EQ(m.menu.slice_at(m.at(45.0 * k + 10.0, 0.03)), k) << k;
    // Held past the delay, the hand at 3 o'clock (Redo), released: chosen, not a flick.
    m.menu.update(m.at(90.0, 0.03), 0.5);
    EXPECT_EQ(m.menu.ring().highlighted, 2);
    const std::optional<MenuChoice> c = m.menu.release(m.at(90.0, 0.03), 0.6);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->action, "edit.redo");
    EXPECT_FALSE(c->flick);
    EXPECT_FALSE(m.menu.is_open());
}

TEST(PieMenu, AFlickChoosesUnseenAndAMarkReachesASubRing) {
    MenuRig m;
    m.menu.open(m.root, Vec3(0.0), m.head, 1.0);
    std::optional<MenuChoice> c = m.menu.release(m.at(270.0, 0.03), 1.12);  // a flick left: Undo
    ASSERT_TRUE(c);
    EXPECT_EQ(c->action, "edit.undo");
    EXPECT_TRUE(c->flick);
    // A two-stroke mark: up past the radius (Operation opens at the hand), then right (Paint is slice 2 of 7).
    m.menu.open(m.root, Vec3(0.0), m.head, 2.0);
    m.menu.update(m.at(0.0, 0.06), 2.05);
    EXPECT_EQ(m.menu.ring().node->label, "Operation");
    const Vec3 sub = m.at(0.0, 0.06);
    c = m.menu.release(sub + m.at(120.0, 0.03), 2.15);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->action, "op.paint");
    EXPECT_TRUE(c->flick);
}

TEST(PieMenu, AClickKeepsTheRingOpenAndASecondClickChoosesOrCloses) {
    MenuRig m;
    m.menu.open(m.root, Vec3(0.0), m.head, 0.0);
    EXPECT_FALSE(m.menu.release(Vec3(0.0), 0.05));  // a click in the centre: stays open, shown
    EXPECT_TRUE(m.menu.is_open());
    EXPECT_TRUE(m.menu.shown(0.06));
    m.menu.press(m.at(180.0, 0.03), 1.0);  // End: a sub-ring, released over it: it opens at the hand
    EXPECT_FALSE(m.menu.release(m.at(180.0, 0.03), 1.1));
    EXPECT_EQ(m.menu.ring().node->label, "End");
    m.menu.press(m.at(180.0, 0.03), 2.0);
    const std::optional<MenuChoice> c = m.menu.release(m.at(180.0, 0.03) + m.at(180.0, 0.03), 2.1);  // Cancel
    ASSERT_TRUE(c);
    EXPECT_EQ(c->action, "");
    EXPECT_EQ(c->label, "Cancel");
    m.menu.open(m.root, Vec3(0.0), m.head, 3.0);
    EXPECT_FALSE(m.menu.release(Vec3(0.0), 3.05));
    m.menu.press(Vec3(0.0), 4.0);
    EXPECT_FALSE(m.menu.release(Vec3(0.0), 4.1));  // a second click in the centre closes
    EXPECT_FALSE(m.menu.is_open());
    // Bad input is ignored.
    m.menu.open(m.root, Vec3(std::nan("")), m.head, 5.0);
    EXPECT_FALSE(m.menu.is_open());
    EXPECT_THROW(PieMenu(PieMenuSettings{0.05, 0.06, 0.25}), Error);
}

TEST(PieMenu, ItsMeshesLieInThePlaneThroughTheHand) {
    MenuRig m;
    const Vec3 hand(0.1, 1.3, 0.7), head(0.0, 1.7, 2.5);
    m.menu.open(m.root, hand, head, 0.0);
    m.menu.update(hand + 0.03 * m.menu.ring().right, 0.5);
    const std::vector<MenuPiece> pieces = pie_menu_pieces(m.menu.ring(), "operation: subtract");
    ASSERT_EQ(pieces.size(), 3u);
    for (const MenuPiece& p : pieces) {
        ASSERT_FALSE(p.mesh.triangles.empty());
        for (const Vec3& v : p.mesh.positions) {
            const double off = glm::dot(v - hand, m.menu.ring().normal);
            EXPECT_GE(off, -1e-9);
            EXPECT_LE(off, 0.0021);
            EXPECT_LT(glm::length(v - hand), 0.2);
        }
    }
    // The lit slice is the one the hand points at (3 o'clock: its vertices lie right of the hand).
    double mean_u = 0.0;
    for (const Vec3& v : pieces[1].mesh.positions) mean_u += glm::dot(v - hand, m.menu.ring().right);
    EXPECT_GT(mean_u / pieces[1].mesh.positions.size(), 0.02);
}

TEST(MenuTrack, KeepsEachChangeAndAnswersWhatWasShownWhen) {
    MenuRig m;
    MenuTrack track;
    track.add(0.5, menu_frame_of(m.menu, 0.5, ""));  // closed before anything: nothing kept
    EXPECT_EQ(track.size(), 0u);
    m.menu.open(m.root, Vec3(0.0), m.head, 1.0);
    track.add(1.1, menu_frame_of(m.menu, 1.1, "s"));  // not shown yet (a flick would be unseen): nothing kept
    EXPECT_EQ(track.size(), 0u);
    m.menu.update(m.at(0.0, 0.06), 1.3);  // shown, Operation's ring opened at the hand
    m.menu.update(m.at(0.0, 0.06) + m.at(60.0, 0.03), 1.35);
    const MenuFrame lit = menu_frame_of(m.menu, 1.4, "operation: subtract");
    track.add(1.4, lit);
    track.add(1.45, lit);  // unchanged: not kept again
    m.menu.close();
    track.add(1.6, menu_frame_of(m.menu, 1.6, ""));
    EXPECT_EQ(track.size(), 2u);
    EXPECT_FALSE(track.at(1.0).shown);
    EXPECT_EQ(track.at(1.5), lit);
    EXPECT_EQ(lit.path, std::vector<std::uint8_t>{0});
    EXPECT_EQ(lit.highlighted, 1);
    EXPECT_EQ(ring_of(lit, m.root).node->children[1].action, "op.union");
    EXPECT_FALSE(track.at(2.0).shown);
    const MenuTrack back = MenuTrack::from_json_text(track.to_json_text(), "rec");
    EXPECT_EQ(back.at(1.5), lit);
    EXPECT_EQ(back.size(), 2u);
    EXPECT_EQ(MenuTrack().to_json_text(), "");
    const std::string e = error_of([] { (void)MenuTrack::from_json_text(R"([{"t_s": 2}, {"t_s": 1}])", "rec"); });
    EXPECT_NE(e.find("rec: menu[1].t_s: decreases"), std::string::npos) << e;
    EXPECT_NE(error_of([] { (void)MenuTrack::from_json_text(R"([{"t_s": 1, "shown": true}])", "rec"); })
                  .find("rec: menu[0].centre_m"),
              std::string::npos);
    // A frame naming a ring this menu does not have draws nothing.
    MenuFrame odd = lit;
    odd.path = {7};
    EXPECT_EQ(ring_of(odd, m.root).node, nullptr);
    EXPECT_TRUE(menu_frame_pieces(odd, m.root).empty());
}

TEST(HandControls, TheToolsMenuButtonOpensChoosesAndBlocksCommandsWhileOpen) {
    HandControls hands(default_bindings("flystick", driver_caps("flystick")), 0.05);
    Recorder r;
    HandsFrame h;
    h.tool_fresh = true;
    h.head_m = Vec3(0.0, 0.0, 0.6);
    const auto frame = [&](double t, std::uint64_t buttons, const Vec3& at, std::vector<std::string> keys = {}) {
        h.t_s = t;
        h.tool_buttons = buttons;
        h.tool_m = at;
        hands.frame(h, keys, r);
    };
    frame(0.0, 0, Vec3(0.0));
    frame(0.1, 1u << 3, Vec3(0.0));  // button2: undo
    EXPECT_EQ(r.did, (std::vector<std::string>{"undo"}));
    frame(0.2, 1u << 2, Vec3(0.0));  // button1: the menu opens at the tool
    EXPECT_TRUE(hands.menu().is_open());
    EXPECT_TRUE(hands.detent().open);
    EXPECT_EQ(hands.detent().slices, 8);
    frame(0.3, (1u << 2) | (1u << 4), Vec3(0.0));  // button3 (redo) while the menu is open: not run
    EXPECT_EQ(r.did.size(), 1u);
    frame(0.6, (1u << 2), Vec3(-0.03, 0.0, 0.0));  // the hand to 9 o'clock: Undo lit
    frame(0.7, 0, Vec3(-0.03, 0.0, 0.0));          // released: chosen
    EXPECT_FALSE(hands.menu().is_open());
    EXPECT_FALSE(hands.detent().open);
    EXPECT_EQ(r.did, (std::vector<std::string>{"undo", "undo"}));
    frame(0.8, 0, Vec3(0.0), {"op.union"});
    const nlohmann::json j = hands.report_json();
    EXPECT_EQ(j.at("menu").at("opens"), 1);
    EXPECT_EQ(j.at("menu").at("choices").at("edit.undo"), 1);
    EXPECT_EQ(j.at("actions").at("edit.undo").at("button"), 1);
    EXPECT_EQ(j.at("actions").at("edit.undo").at("menu"), 1);
    EXPECT_EQ(j.at("actions").at("op.union").at("key"), 1);
    // The desk's middle button opens it at the tool too.
    h.desk_menu = true;
    frame(1.0, 0, Vec3(0.0));
    EXPECT_TRUE(hands.menu().is_open());
}

}  // namespace
}  // namespace tridex::app
