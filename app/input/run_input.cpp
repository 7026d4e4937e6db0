// app/input/run_input.cpp - keyboard and mouse to head and scene.
#include "app/input/run_input.hpp"

#include <cmath>
#include <utility>

namespace tridex::app {

namespace {

using renderer::InputAction;
using renderer::InputType;
using renderer::Key;
using renderer::MoveKey;

// The head motion a key stands for; false when the key moves nothing.
bool move_key(Key k, MoveKey& out) {
    switch (k) {
        case Key::kW: case Key::kUp: out = MoveKey::kForward; return true;
        case Key::kS: case Key::kDown: out = MoveKey::kBack; return true;
        case Key::kA: case Key::kLeft: out = MoveKey::kLeft; return true;
        case Key::kD: case Key::kRight: out = MoveKey::kRight; return true;
        case Key::kR: out = MoveKey::kUp; return true;
        case Key::kF: out = MoveKey::kDown; return true;
        default: return false;
    }
}

}  // namespace

RunInput::RunInput(renderer::KeyboardMouseHead* head, renderer::SceneNavigation& nav,
                   const renderer::MouseNavigation& mouse)
    : head_(head), nav_(nav), mouse_(mouse) {}

std::vector<std::string> RunInput::take_actions() { return std::exchange(actions_, {}); }

void RunInput::handle(const renderer::InputEvent& e) {
    switch (e.type) {
        case InputType::kKey: {
            if (e.key == Key::kLeftShift || e.key == Key::kRightShift) shift_ = e.action != InputAction::kRelease;
            if (e.key == Key::kLeftAlt || e.key == Key::kRightAlt) alt_ = e.action != InputAction::kRelease;
            if (const KeyBinding* b = find_key_binding(e.key, e.modifiers, stylus_ != nullptr)) {
                if (e.action == InputAction::kPress || (e.action == InputAction::kRepeat && b->repeats))
                    actions_.push_back(b->action);
                return;
            }
            if (e.action == InputAction::kRepeat) return;
            MoveKey mk;
            if (move_key(e.key, mk) && head_) head_->key(mk, e.action == InputAction::kPress);
            return;
        }
        case InputType::kMouseButton: {
            const bool down = e.action != InputAction::kRelease;
            if (e.button == renderer::MouseButton::kMiddle) {  // the menu button, in both modes
                middle_ = down;
                if (stylus_) stylus_->set_cursor(e.x_px, e.y_px);
                return;
            }
            if (stylus_) {
                stylus_->set_cursor(e.x_px, e.y_px);
                const bool alt = (e.modifiers & renderer::modifier::kAlt) != 0;
                alt_ = alt;
                // A press goes to the stylus unless Alt is held; a release ends whichever it started.
                if (e.button == renderer::MouseButton::kLeft && (!down || !alt)) stylus_->set_left(down);
                if (e.button == renderer::MouseButton::kRight && (!down || !alt)) stylus_->set_right(down);
                if (down && !alt) return;
            }
            if (e.button == renderer::MouseButton::kLeft) left_ = down;
            if (e.button == renderer::MouseButton::kRight) right_ = down;
            shift_ = (e.modifiers & renderer::modifier::kShift) != 0;
            return;
        }
        case InputType::kMouseMove: {
            if (stylus_) stylus_->set_cursor(e.x_px, e.y_px);
            if (!std::isfinite(e.dx_px) || !std::isfinite(e.dy_px)) return;
            if (left_ && shift_)
                renderer::mouse_pan(nav_, mouse_, e.dx_px, e.dy_px);
            else if (left_)
                renderer::mouse_orbit(nav_, mouse_, e.dx_px, e.dy_px);
            else if (right_ && head_)
                head_->mouse_turn(e.dx_px, e.dy_px);
            return;
        }
        case InputType::kScroll:
            if (stylus_ && !alt_) {  // scroll events carry no modifiers: Alt as the key events left it
                if (std::isfinite(e.dy_px)) stylus_->wheel(e.dy_px);
                return;
            }
            if (std::isfinite(e.dy_px) && e.dy_px != 0.0) renderer::mouse_zoom(nav_, mouse_, e.dy_px);
            return;
    }
}

}  // namespace tridex::app
