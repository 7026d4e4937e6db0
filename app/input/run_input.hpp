// app/input/run_input.hpp - keyboard and mouse controls of a `tridex run` window when no tracker drives the head.
#pragma once

#include <cmath>
#include <vector>

#include <string>

#include "app/input/key_bindings.hpp"
#include "app/input/mouse_stylus.hpp"
#include "renderer/camera/head_pose.hpp"
#include "renderer/camera/scene_navigation.hpp"
#include "renderer/window/window_input.hpp"

namespace tridex::app {

/// Maps window input events to the head and the scene (the paper's Wand, played by the mouse):
/// - W / S or Up / Down: head forward / back; A / D or Left / Right: left / right; R / F: up / down (held keys,
///   KeyboardMouseHead speed); right-button drag turns the head (only when a KeyboardMouseHead is given);
/// - left-button drag orbits the scene about the pivot, Shift + left drag pans it, the wheel scales it (renderer
///   mouse_orbit / mouse_pan / mouse_zoom);
/// - the middle button is the menu button: held, the pie menu is open (menu_held());
/// - every other key chord of desk_key_bindings() (Home, Tab, O, Esc, Ctrl+Z, Ctrl+Shift+Z, Ctrl+Y, Ctrl+S, and with
///   the stylus 1..6, [ and ]) names an action, queued in the order pressed (take_actions()); the caller runs them
///   (app/actions/action_registry.hpp). A bound chord never moves the head.
/// With a mouse stylus (use_stylus; `--device mouse`) the mouse is the tool instead: the left button engages it,
/// the right button is the stylus button, the wheel sets the depth, and scene navigation moves to Alt: Alt + left
/// drag orbits, Alt + Shift + left drag pans, Alt + wheel zooms, Alt + right drag turns the head.
/// One thread (the window's); the head and navigation must outlive it.
class RunInput {
public:
    /// `head`: the keyboard-and-mouse head, or nullptr when a script or tracker drives the head (keys then
    /// move nothing); `nav` and `mouse`: the scene navigation and its mouse gains/axes.
    RunInput(renderer::KeyboardMouseHead* head, renderer::SceneNavigation& nav, const renderer::MouseNavigation& mouse);
    /// The screen's metres per window pixel for mouse navigation (MouseNavigation::metres_per_pixel), after the
    /// window or the screen it shows changed size; values that are not finite and positive are ignored.
    void set_metres_per_pixel(double m) {
        if (std::isfinite(m) && m > 0.0) mouse_.metres_per_pixel = m;
    }

    /// Makes the mouse the stylus (nullptr: the mouse navigates again); `stylus` must outlive this.
    void use_stylus(MouseStylus* stylus) { stylus_ = stylus; }
    /// Applies one event. Never throws for finite event values (non-finite deltas are ignored).
    void handle(const renderer::InputEvent& event);
    /// The actions the keys named since the last call, in the order pressed (auto-repeat included where the
    /// binding repeats, so holding Ctrl+Z undoes stroke after stroke).
    std::vector<std::string> take_actions();
    /// True while the middle button (the menu button at the desk) is held.
    bool menu_held() const { return middle_; }

private:
    renderer::KeyboardMouseHead* head_;
    renderer::SceneNavigation& nav_;
    renderer::MouseNavigation mouse_;
    MouseStylus* stylus_ = nullptr;
    bool left_ = false, right_ = false, middle_ = false, shift_ = false, alt_ = false;
    std::vector<std::string> actions_;
};

}  // namespace tridex::app
