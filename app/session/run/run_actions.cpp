// app/session/run/run_actions.cpp - the run session's actions and the hands' controls (bindings, pie menu).
#include "app/session/run/run_actions.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.hpp"

namespace tridex::app {

namespace {

// A joystick bound to tool.scale steps the tool this often while tilted past half way, s.
constexpr double kToolScaleRepeatS = 0.4;

double checked_ring_radius(double r) {
    if (!(std::isfinite(r) && r > 0.0)) throw Error("the menu's radius must be finite and > 0 m");
    return r;
}

}  // namespace

RunActions::RunActions(SessionRuntime* runtime, MouseStylus* mouse, renderer::SceneNavigation& nav,
                       renderer::KeyboardMouseHead* head, bool& swap, bool& ao, const ToolShape& tool)
    : runtime_(runtime), mouse_(mouse), nav_(nav), head_(head), swap_(swap), ao_(ao), base_tool_(tool),
      op_(runtime ? runtime->tool_op() : ToolOp::kSubtract),
      symmetry_on_(runtime && runtime->symmetry().on() ? runtime->symmetry() : Symmetry{Symmetry::kMirrorX, 0, 0}) {}

void RunActions::toggle_symmetry() {
    if (runtime_) runtime_->set_symmetry(runtime_->symmetry().on() ? Symmetry{} : symmetry_on_);
}

void RunActions::next_workpiece() {
    if (!runtime_ || runtime_->workpiece_count() < 2) return;
    const int n = static_cast<int>(runtime_->workpiece_count());
    const int k = runtime_->chosen_workpiece() + 1;  // -1 (automatic) -> 0 -> ... -> n-1 -> -1
    (void)runtime_->choose_workpiece(k >= n ? -1 : k);
}

void RunActions::set_op(ToolOp op) {
    if (op == ToolOp::kNone) return;
    op_ = op;
    if (mouse_)
        mouse_->set_op(op);  // RunMouse hands it to the loop with the operation's own depth
    else if (runtime_)
        runtime_->set_tool_op(op);
}

ToolOp RunActions::op() const {
    if (mouse_) return mouse_->op();
    if (runtime_) return runtime_->tool_op();
    return op_;
}

void RunActions::set_material(std::uint8_t id) {
    if (id < 1 || id > kMaxMaterialId) return;
    material_ = id;
    if (runtime_) runtime_->set_material(id);  // the mouse stylus hands on operations only: the loop keeps this
}

std::uint8_t RunActions::material() const { return runtime_ ? runtime_->material() : material_; }

bool RunActions::resize_tool(int steps) {
    if (mouse_) return mouse_->resize(steps);
    if (base_tool_.kind == ToolKind::kMesh) return false;
    const int want = std::clamp(size_steps_ + steps, -MouseStylus::kMaxSizeSteps, MouseStylus::kMaxSizeSteps);
    if (want == size_steps_) return false;
    ToolShape t = base_tool_;
    const double f = std::pow(MouseStylus::kSizeStep, want);
    t.radius_m *= f;
    t.length_m *= f;
    if (runtime_ && !runtime_->set_tool(t)) return false;
    size_steps_ = want;
    return true;
}

bool RunActions::request(SculptRequest r) {
    if (!runtime_) return false;
    if (!runtime_->request(r)) {
        ++dropped_;
        return false;
    }
    ++requests_sent_;
    if (r == SculptRequest::kSave) ++saves_sent_;
    return true;
}

void RunActions::reset_scene() {
    if (head_) head_->reset();
    nav_.reset();
}

HandControls::HandControls(Bindings bindings, double ring_radius_m, const MaterialPalette& palette)
    : bindings_(std::move(bindings)), tool_(bindings_.tool), wand_(bindings_.wand),
      ring_radius_m_(checked_ring_radius(ring_radius_m)), root_(default_menu(palette)),
      menu_(PieMenuSettings{ring_radius_m_, 0.24 * ring_radius_m_, 0.25}) {}

bool HandControls::run(const std::string& action, const std::string& source, ActionTarget& target) {
    if (!builtin_actions().run(action, target)) return false;
    ++actions_[action][source];
    return true;
}

void HandControls::drive_menu(bool held, const Vec3& hand_m, const HandsFrame& h, ActionTarget& target) {
    const bool pressed = held && !menu_held_, released = !held && menu_held_;
    menu_held_ = held;
    if (pressed && !menu_.is_open()) {
        const double size = h.ring_radius_m > 0.0 && std::isfinite(h.ring_radius_m) ? h.ring_radius_m / ring_radius_m_
                            : h.scene_scale > 0.0 && std::isfinite(h.scene_scale) ? 1.0 / h.scene_scale
                                                                                  : 1.0;
        menu_.open(root_, hand_m, h.head_m, h.t_s, size);
        if (menu_.is_open()) ++opens_;
        return;
    }
    if (!menu_.is_open()) return;
    if (pressed) menu_.press(hand_m, h.t_s);
    if (!released) {
        menu_.update(hand_m, h.t_s);
        return;
    }
    const std::optional<MenuChoice> c = menu_.release(hand_m, h.t_s);
    if (!c) {
        if (!menu_.is_open()) ++cancels_;
        return;
    }
    if (c->action.empty()) {  // the Cancel slice
        ++cancels_;
        return;
    }
    if (c->flick) ++flicks_;
    ++choices_[c->action];
    run(c->action, "menu", target);
}

void HandControls::frame(const HandsFrame& h, const std::vector<std::string>& keys, ActionTarget& target) {
    std::vector<std::string> pressed;
    if (h.tool_fresh) tool_.update(h.tool_buttons, pressed);
    if (h.wand_fresh) wand_.update(h.wand_buttons, pressed);
    for (const std::string& k : keys) run(k, "key", target);
    // The menu follows the hand whose button opened it; the desk's middle button opens it at the tool.
    const bool wand_menu = h.wand_fresh && wand_.held("menu");
    const bool tool_menu = (h.tool_fresh && tool_.held("menu")) || h.desk_menu;
    if (!menu_.is_open() && !menu_held_) menu_by_wand_ = wand_menu && !tool_menu;
    const bool held = menu_by_wand_ ? wand_menu : tool_menu;
    Vec3 hand = menu_by_wand_ ? h.wand_m : h.tool_m;
    if (menu_.is_open() && !menu_by_wand_ && h.pointer_ray) {  // the cursor's ray on the ring's plane
        const RingView& r = menu_.ring();
        const double along = glm::dot(h.pointer_ray->dir, r.normal);
        if (std::abs(along) > 1e-9) {
            const double t = glm::dot(r.centre_m - h.pointer_ray->origin_m, r.normal) / along;
            if (t > 0.0 && std::isfinite(t)) hand = h.pointer_ray->origin_m + t * h.pointer_ray->dir;
        }
    }
    drive_menu(held, hand, h, target);
    if (menu_.is_open()) return;  // while choosing, no button's command runs
    for (const std::string& a : pressed) run(a, "button", target);
    // A joystick bound to tool.scale (the tool's or the wand's) steps the tool while tilted past half way.
    double tilt = 0.0;
    if (bindings_.tool.joystick_y == "tool.scale" && h.tool_fresh) tilt = h.tool_joystick_y;
    if (bindings_.wand.joystick_y == "tool.scale" && h.wand_fresh && std::abs(h.wand_joystick_y) > std::abs(tilt))
        tilt = h.wand_joystick_y;
    if (std::abs(tilt) > 0.5 && h.t_s >= tool_scale_next_s_) {
        if (target.resize_tool(tilt > 0.0 ? 1 : -1)) ++actions_["tool.scale"]["axis"];
        tool_scale_next_s_ = h.t_s + kToolScaleRepeatS;
    }
}

haptics::MenuDetent HandControls::detent() const {
    haptics::MenuDetent d;
    if (!menu_.is_open() || menu_by_wand_ || !menu_.ring().node) return d;
    const RingView& r = menu_.ring();
    d.open = true;
    d.centre_m = r.centre_m;
    d.right = r.right;
    d.up = r.up;
    d.slices = static_cast<int>(r.node->children.size());
    d.dead_radius_m = r.dead_radius_m;
    return d;
}

nlohmann::json HandControls::report_json() const {
    nlohmann::json choices = nlohmann::json::object();
    for (const auto& [a, n] : choices_) choices[a] = n;
    nlohmann::json actions = nlohmann::json::object();
    for (const auto& [a, by] : actions_) {
        nlohmann::json o = nlohmann::json::object();
        for (const auto& [src, n] : by) o[src] = n;
        actions[a] = o;
    }
    return {{"bindings", bindings_json(bindings_)},
            {"menu", {{"opens", opens_}, {"flicks", flicks_}, {"cancels", cancels_}, {"choices", choices},
                      {"radius_m", ring_radius_m_}}},
            {"actions", actions}};
}

}  // namespace tridex::app
