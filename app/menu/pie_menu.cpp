// app/menu/pie_menu.cpp - the pie menu's rings, its hand-direction choice and its flicks.
#include "app/menu/pie_menu.hpp"

#include <cmath>
#include <numbers>

#include "app/actions/action_registry.hpp"
#include "core/error.hpp"

namespace tridex::app {

namespace {

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

MenuItem leaf(const std::string& action) {
    const Action& a = builtin_actions().get(action, "default_menu");
    return MenuItem{a.label, a.glyph, a.name, {}};
}

MenuItem branch(std::string label, std::string glyph, std::vector<MenuItem> children) {
    return MenuItem{std::move(label), std::move(glyph), "", std::move(children)};
}

// The materials union adds and paint sets, each slice labelled with the palette's name for it.
MenuItem colour_branch(const MaterialPalette& palette) {
    MenuItem colours = branch("Colour", "...", {});
    for (int m = 1; m <= kMaxMaterialId; ++m) {
        MenuItem slice = leaf("material." + std::to_string(m));
        slice.label = palette[m].name;
        colours.children.push_back(std::move(slice));
    }
    return colours;
}

}  // namespace

MenuItem default_menu(const MaterialPalette& palette) {
    MenuItem root{"Menu", "", "", {}};
    root.children = {
        branch("Operation", "...", {leaf("op.subtract"), leaf("op.union"), leaf("op.paint"), leaf("op.push"),
                                    leaf("op.smooth"), leaf("op.pull"), leaf("op.grab")}),
        // Larger and Smaller keep their directions (up, down); Finer and Coarser (the model's coarseness) below the
        // colours and the symmetry, on either side.
        branch("Tool", "...", {leaf("tool.larger"), colour_branch(palette), leaf("coarseness.finer"), leaf("tool.smaller"),
                               leaf("coarseness.coarser"), leaf("symmetry.toggle")}),
        leaf("edit.redo"),
        leaf("file.save"),
        branch("End", "...", {leaf("session.end"), MenuItem{"Cancel", "", "", {}}}),
        // Place (the whole workpiece follows the tool) arranges the scene, as the view's slices do.
        // Choosing the workpiece the tool carves (of several) arranges it too.
        branch("View", "...", {leaf("view.reset"), leaf("view.swap_eyes"), leaf("view.occlusion"), leaf("workpiece.next"),
                               leaf("op.place")}),
        leaf("edit.undo"),
        leaf("op.next"),
    };
    return root;
}

PieMenu::PieMenu(PieMenuSettings s) : settings_(s) {
    if (!std::isfinite(s.radius_m) || !std::isfinite(s.dead_radius_m) || !std::isfinite(s.show_delay_s))
        throw Error("PieMenuSettings: radius_m, dead_radius_m and show_delay_s must be finite");
    if (!(s.dead_radius_m > 0.0 && s.dead_radius_m < s.radius_m))
        throw Error("PieMenuSettings.dead_radius_m: must be between 0 and radius_m");
    if (s.show_delay_s < 0.0) throw Error("PieMenuSettings.show_delay_s: must be >= 0");
}

void PieMenu::open_ring(const MenuItem& node, const Vec3& centre_m) {
    ring_.node = &node;
    ring_.centre_m = centre_m;
    ring_.highlighted = -1;
}

void PieMenu::open(const MenuItem& root, const Vec3& hand_m, const Vec3& head_m, double t_s, double size) {
    if (open_ || !finite(hand_m) || !finite(head_m) || !std::isfinite(t_s) || !root.branch()) return;
    if (!(std::isfinite(size) && size > 0.0)) return;
    Vec3 n = head_m - hand_m;
    if (glm::length(n) < 1e-9) n = Vec3(0.0, 0.0, 1.0);
    n = glm::normalize(n);
    Vec3 up = Vec3(0.0, 1.0, 0.0) - n * n.y;
    if (glm::length(up) < 1e-6) up = Vec3(0.0, 0.0, 1.0) - n * n.z;
    up = glm::normalize(up);
    ring_.normal = n;
    ring_.up = up;
    ring_.right = glm::normalize(glm::cross(up, n));
    ring_.radius_m = settings_.radius_m * size;
    ring_.dead_radius_m = settings_.dead_radius_m * size;
    open_ring(root, hand_m);
    path_.clear();
    open_ = true;
    sticky_ = false;
    pressed_again_ = false;
    opened_at_s_ = t_s;
}

int PieMenu::slice_at(const Vec3& hand_m) const {
    if (!open_ || !finite(hand_m) || !ring_.node) return -1;
    const Vec3 d = hand_m - ring_.centre_m;
    const double x = glm::dot(d, ring_.right), y = glm::dot(d, ring_.up);
    if (std::hypot(x, y) < ring_.dead_radius_m) return -1;
    const int n = static_cast<int>(ring_.node->children.size());
    // Clockwise from 12 o'clock, as seen from the head.
    double a = std::atan2(x, y);  // 0 at +up, growing toward +right
    if (a < 0.0) a += 2.0 * std::numbers::pi;
    const double w = 2.0 * std::numbers::pi / n;
    return static_cast<int>(std::floor(a / w + 0.5)) % n;
}

void PieMenu::update(const Vec3& hand_m, double t_s) {
    if (!open_ || !finite(hand_m) || !std::isfinite(t_s)) return;
    ring_.highlighted = slice_at(hand_m);
    if (ring_.highlighted < 0) return;
    const MenuItem& item = ring_.node->children[static_cast<std::size_t>(ring_.highlighted)];
    if (item.branch() && glm::length(hand_m - ring_.centre_m) > ring_.radius_m) {
        path_.push_back(static_cast<std::uint8_t>(ring_.highlighted));
        open_ring(item, hand_m);
    }
}

void PieMenu::press(const Vec3& hand_m, double t_s) {
    if (!open_ || !sticky_) return;
    pressed_again_ = true;
    update(hand_m, t_s);
}

std::optional<MenuChoice> PieMenu::release(const Vec3& hand_m, double t_s) {
    if (!open_) return std::nullopt;
    update(hand_m, t_s);
    const bool unseen = !shown(t_s);
    if (ring_.highlighted < 0) {
        // A click in the centre opens the ring and keeps it; a second click there (or a held release) closes it.
        if (!sticky_ && unseen) {
            sticky_ = true;
            return std::nullopt;
        }
        close();
        return std::nullopt;
    }
    const MenuItem& item = ring_.node->children[static_cast<std::size_t>(ring_.highlighted)];
    if (item.branch()) {  // released over a sub-ring: it opens at the hand, for a second click
        path_.push_back(static_cast<std::uint8_t>(ring_.highlighted));
        open_ring(item, hand_m);
        sticky_ = true;
        return std::nullopt;
    }
    MenuChoice c{item.action, item.label, unseen};
    close();
    return c;
}

void PieMenu::close() {
    open_ = false;
    sticky_ = false;
    pressed_again_ = false;
    ring_.highlighted = -1;
    ring_.node = nullptr;
    path_.clear();
}

bool PieMenu::shown(double t_s) const {
    return open_ && (sticky_ || t_s - opened_at_s_ >= settings_.show_delay_s);
}

}  // namespace tridex::app
