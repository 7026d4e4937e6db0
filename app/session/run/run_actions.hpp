// app/session/run/run_actions.hpp - what actions do in a `tridex run` session (ActionTarget), and the hands' controls:
// device buttons through their bindings, and the pie menu at the hand.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/actions/action_registry.hpp"
#include "app/actions/bindings.hpp"
#include "app/input/surface_pick.hpp"
#include "app/menu/pie_menu.hpp"
#include "app/session/run/run_mouse.hpp"
#include "app/session/runtime/session_runtime.hpp"
#include "core/symmetry.hpp"
#include "haptics/menu_detent.hpp"
#include "renderer/camera/head_pose.hpp"
#include "renderer/camera/scene_navigation.hpp"

namespace tridex::app {

/// The session's ActionTarget: operations and tool sizes go to the mouse stylus when the mouse is the tool (it hands
/// them to the loop with its own per-operation depth), else straight to the haptic loop; undo, redo and save to the
/// sculpt thread; the view's toggles to the frame loop's flags. One thread (the frame loop's).
class RunActions final : public ActionTarget {
public:
    /// `runtime` may be null (tests); `mouse` null unless the mouse is the stylus; `head` null unless a keyboard
    /// head is used; `swap`, `ao` the frame loop's flags; `tool` the scene's tool (resize_tool scales it).
    RunActions(SessionRuntime* runtime, MouseStylus* mouse, renderer::SceneNavigation& nav,
               renderer::KeyboardMouseHead* head, bool& swap, bool& ao, const ToolShape& tool);
    void set_op(ToolOp op) override;
    ToolOp op() const override;
    void set_material(std::uint8_t id) override;
    std::uint8_t material() const override;
    bool resize_tool(int steps) override;
    bool request(SculptRequest r) override;
    void reset_scene() override;
    void swap_eyes() override { swap_ = !swap_; }
    void toggle_occlusion() override { ao_ = !ao_; }
    void toggle_symmetry() override;
    void next_workpiece() override;
    void end_session() override { end_ = true; }

    bool end_requested() const { return end_; }                     ///< session.end was done
    std::uint64_t requests_sent() const { return requests_sent_; }  ///< undo, redo and save handed over
    std::uint64_t saves_sent() const { return saves_sent_; }        ///< of those, saves
    std::uint64_t requests_dropped() const { return dropped_; }     ///< refused by a full queue

private:
    SessionRuntime* runtime_;
    MouseStylus* mouse_;
    renderer::SceneNavigation& nav_;
    renderer::KeyboardMouseHead* head_;
    bool& swap_;
    bool& ao_;
    ToolShape base_tool_;
    int size_steps_ = 0;
    ToolOp op_;  // without a runtime or stylus: the last set
    Symmetry symmetry_on_;  // what toggle_symmetry turns on: the session's symmetry, else a mirror across x
    std::uint8_t material_ = 1;  // without a runtime: the last set
    bool end_ = false;
    std::uint64_t requests_sent_ = 0, saves_sent_ = 0, dropped_ = 0;
};

/// What the hands did in one frame (the frame loop gathers it; positions in the scene's frame, m).
struct HandsFrame {
    double t_s = 0.0;                 ///< the haptic loop's time of the view, s (menu timing, flicks)
    std::uint64_t tool_buttons = 0;   ///< the tool device's buttons (LoopView::buttons)
    bool tool_fresh = false;          ///< the loop has ticked (its buttons and position are the device's)
    Vec3 tool_m{0.0};                 ///< the tool (HIP), scene m
    double tool_joystick_y = 0.0;     ///< the tool device's joystick in [-1, 1] (LoopView::joystick_y)
    bool desk_menu = false;           ///< the desk's menu button (the middle mouse button) is held
    bool wand_fresh = false;          ///< a tracked wand sample this frame
    std::uint64_t wand_buttons = 0;   ///< its buttons (bit i = Flystick button i)
    Vec3 wand_m{0.0};                 ///< its position, scene m
    double wand_joystick_y = 0.0;     ///< its joystick's y in [-1, 1]
    Vec3 head_m{0.0};                 ///< the cyclopean eye, scene m
    double scene_scale = 1.0;         ///< world m per scene m (the menu keeps its size in the world)
    /// A desk pointer's ray through the cursor (scene m): while the menu opened at the tool is open, the hand is where
    /// it meets the ring's plane, so the cursor points at the slices as the mouse moves. nullopt: the tool is the hand.
    std::optional<Ray> pointer_ray;
    /// > 0: the radius of a ring opened now, scene m (a desk pointer's: a fixed size on screen at the tool's depth);
    /// 0: HandControls' radius in the world.
    double ring_radius_m = 0.0;
};

/// The hands' controls: per frame, the tool device's and the wand's button presses run their bound commands (in
/// device order: tool, then wand), a held menu button opens the pie menu at that hand (the desk's middle button:
/// at the tool), and its release chooses. While the menu is open no bound command runs. Counts what was done, for
/// report.json `controls`. One thread (the frame loop's).
class HandControls {
public:
    /// `ring_radius_m`: the menu's radius in the world, m (finite, > 0; its dead zone is 0.24 of it, and the ring shows
    /// after 0.25 s held). `palette` names the menu's Colour slices (default_menu). Throws tridex::Error for a bad
    /// radius.
    HandControls(Bindings bindings, double ring_radius_m = 0.05,
                 const MaterialPalette& palette = default_material_palette());
    /// One frame: runs the desk's `keys` (action names, in the order pressed), reads the buttons, drives the menu,
    /// runs the chosen and pressed commands on `target`, and steps the tool while a joystick bound to tool.scale is
    /// tilted past half way (a step every 0.4 s of h.t_s). Unknown names and held or axis actions in `keys` are
    /// skipped. Never throws for finite input; non-finite positions and times are ignored by the menu.
    void frame(const HandsFrame& h, const std::vector<std::string>& keys, ActionTarget& target);
    /// Runs one named command on `target` from `source` ("key", "button", "menu"), counted; false when unknown.
    bool run(const std::string& action, const std::string& source, ActionTarget& target);
    /// The menu (open or not).
    const PieMenu& menu() const { return menu_; }
    /// The menu's items (its root).
    const MenuItem& root() const { return root_; }
    /// The menu as the haptic loop feels it (closed when the menu is closed or was opened by the wand).
    haptics::MenuDetent detent() const;
    /// The bindings read (the tool's and the wand's buttons and joysticks).
    const Bindings& bindings() const { return bindings_; }
    /// report.json `controls`: {bindings, menu {opens, flicks, cancels, choices {action: n}}, actions {action:
    /// {key, button, menu}}}.
    nlohmann::json report_json() const;

private:
    void drive_menu(bool held, const Vec3& hand_m, const HandsFrame& h, ActionTarget& target);

    Bindings bindings_;
    BindingReader tool_, wand_;
    double ring_radius_m_;
    MenuItem root_ = default_menu();
    PieMenu menu_;
    bool menu_held_ = false;     // the menu button was held last frame
    bool menu_by_wand_ = false;  // the open menu follows the wand
    double tool_scale_next_s_ = 0.0;
    std::uint64_t opens_ = 0, flicks_ = 0, cancels_ = 0;
    std::map<std::string, std::uint64_t> choices_;
    std::map<std::string, std::map<std::string, std::uint64_t>> actions_;
};

}  // namespace tridex::app
