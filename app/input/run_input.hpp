// app/input/run_input.hpp - keyboard and mouse controls of a `tridex run` window when no tracker drives the head.
#pragma once

#include <cmath>
#include <vector>

#include "app/input/mouse_stylus.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "renderer/camera/head_pose.hpp"
#include "renderer/camera/scene_navigation.hpp"
#include "renderer/window/window_input.hpp"

namespace tridex::app {

/// Maps window input events to the head and the scene (the paper's Wand, played by the mouse):
/// - W / S or Up / Down: head forward / back; A / D or Left / Right: left / right; R / F: up / down (held keys,
///   KeyboardMouseHead speed); right-button drag turns the head (only when a KeyboardMouseHead is given);
/// - left-button drag orbits the scene about the pivot, Shift + left drag or middle drag pans it, the wheel
///   scales it (renderer mouse_orbit / mouse_pan / mouse_zoom);
/// - Home resets head and scene; Tab toggles swap eyes; O toggles ambient occlusion; Esc asks to close;
/// - Ctrl+Z undoes the last stroke, Ctrl+Shift+Z or Ctrl+Y redoes it, Ctrl+S saves the model (take_requests());
///   with Ctrl held, the letter keys do not move the head.
/// With a mouse stylus (use_stylus; `--device mouse`) the mouse is the tool instead: the left button engages it,
/// the right button is the stylus button, the wheel sets the depth, 1 / 2 / 3 choose subtract / union / paint,
/// 4 / 5 / 6 push / smooth / pull (clay),
/// [ / ] make the tool smaller / larger (MouseStylus::resize),
/// and scene navigation moves to Alt: Alt + left drag orbits, Alt + Shift + left drag (or middle drag) pans,
/// Alt + wheel zooms, Alt + right drag turns the head.
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
    /// True once Esc was pressed.
    bool close_requested() const { return close_; }
    /// How many times Tab was pressed since the last call (the caller flips swap eyes that many times).
    int take_swap_toggles();
    /// How many times O was pressed since the last call (the caller flips ambient occlusion that many times).
    int take_occlusion_toggles();
    /// The undo, redo and save requests since the last call, in the order the keys were pressed (auto-repeat
    /// included, so holding Ctrl+Z undoes stroke after stroke).
    std::vector<SculptRequest> take_requests();

private:
    renderer::KeyboardMouseHead* head_;
    renderer::SceneNavigation& nav_;
    renderer::MouseNavigation mouse_;
    MouseStylus* stylus_ = nullptr;
    bool left_ = false, right_ = false, middle_ = false, shift_ = false, alt_ = false;
    bool close_ = false;
    int swaps_ = 0;
    int occlusion_toggles_ = 0;
    std::vector<SculptRequest> requests_;
};

}  // namespace tridex::app
