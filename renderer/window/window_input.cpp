// renderer/window/window_input.cpp - GLFW codes -> abstract input events, and the event ring.
#include "renderer/window/window_input.hpp"

#include <limits>

#include <array>

#include <GLFW/glfw3.h>

namespace tridex::renderer {
namespace {

struct KeyName {
    int glfw;
    Key key;
    std::string_view name;
};

// Every mapped key (letters and digits are handled by range).
constexpr std::array kNamedKeys{
    KeyName{GLFW_KEY_SPACE, Key::kSpace, "Space"},
    KeyName{GLFW_KEY_ESCAPE, Key::kEscape, "Escape"},
    KeyName{GLFW_KEY_ENTER, Key::kEnter, "Enter"},
    KeyName{GLFW_KEY_TAB, Key::kTab, "Tab"},
    KeyName{GLFW_KEY_BACKSPACE, Key::kBackspace, "Backspace"},
    KeyName{GLFW_KEY_LEFT, Key::kLeft, "Left"},
    KeyName{GLFW_KEY_RIGHT, Key::kRight, "Right"},
    KeyName{GLFW_KEY_UP, Key::kUp, "Up"},
    KeyName{GLFW_KEY_DOWN, Key::kDown, "Down"},
    KeyName{GLFW_KEY_PAGE_UP, Key::kPageUp, "PageUp"},
    KeyName{GLFW_KEY_PAGE_DOWN, Key::kPageDown, "PageDown"},
    KeyName{GLFW_KEY_HOME, Key::kHome, "Home"},
    KeyName{GLFW_KEY_END, Key::kEnd, "End"},
    KeyName{GLFW_KEY_INSERT, Key::kInsert, "Insert"},
    KeyName{GLFW_KEY_DELETE, Key::kDelete, "Delete"},
    KeyName{GLFW_KEY_LEFT_SHIFT, Key::kLeftShift, "LeftShift"},
    KeyName{GLFW_KEY_RIGHT_SHIFT, Key::kRightShift, "RightShift"},
    KeyName{GLFW_KEY_LEFT_CONTROL, Key::kLeftControl, "LeftControl"},
    KeyName{GLFW_KEY_RIGHT_CONTROL, Key::kRightControl, "RightControl"},
    KeyName{GLFW_KEY_LEFT_ALT, Key::kLeftAlt, "LeftAlt"},
    KeyName{GLFW_KEY_RIGHT_ALT, Key::kRightAlt, "RightAlt"},
    KeyName{GLFW_KEY_F1, Key::kF1, "F1"},
    KeyName{GLFW_KEY_F2, Key::kF2, "F2"},
    KeyName{GLFW_KEY_F3, Key::kF3, "F3"},
    KeyName{GLFW_KEY_F4, Key::kF4, "F4"},
    KeyName{GLFW_KEY_F5, Key::kF5, "F5"},
    KeyName{GLFW_KEY_F6, Key::kF6, "F6"},
    KeyName{GLFW_KEY_F7, Key::kF7, "F7"},
    KeyName{GLFW_KEY_F8, Key::kF8, "F8"},
    KeyName{GLFW_KEY_F9, Key::kF9, "F9"},
    KeyName{GLFW_KEY_F10, Key::kF10, "F10"},
    KeyName{GLFW_KEY_F11, Key::kF11, "F11"},
    KeyName{GLFW_KEY_F12, Key::kF12, "F12"},
    KeyName{GLFW_KEY_MINUS, Key::kMinus, "Minus"},
    KeyName{GLFW_KEY_EQUAL, Key::kEqual, "Equal"},
    KeyName{GLFW_KEY_COMMA, Key::kComma, "Comma"},
    KeyName{GLFW_KEY_PERIOD, Key::kPeriod, "Period"},
    KeyName{GLFW_KEY_LEFT_BRACKET, Key::kLeftBracket, "LeftBracket"},
    KeyName{GLFW_KEY_RIGHT_BRACKET, Key::kRightBracket, "RightBracket"},
    KeyName{GLFW_KEY_KP_ADD, Key::kKeypadAdd, "KeypadAdd"},
    KeyName{GLFW_KEY_KP_SUBTRACT, Key::kKeypadSubtract, "KeypadSubtract"},
};

constexpr std::string_view kLetters[26] = {"A", "B", "C", "D", "E", "F", "G", "H", "I", "J", "K", "L", "M",
                                           "N", "O", "P", "Q", "R", "S", "T", "U", "V", "W", "X", "Y", "Z"};
constexpr std::string_view kDigits[10] = {"0", "1", "2", "3", "4", "5", "6", "7", "8", "9"};

bool action_from_glfw(int glfw_action, InputAction& out) {
    switch (glfw_action) {
        case GLFW_PRESS: out = InputAction::kPress; return true;
        case GLFW_RELEASE: out = InputAction::kRelease; return true;
        case GLFW_REPEAT: out = InputAction::kRepeat; return true;
        default: return false;
    }
}

}  // namespace

std::string_view to_string(Key key) {
    const auto k = static_cast<int>(key);
    if (k >= static_cast<int>(Key::kA) && k <= static_cast<int>(Key::kZ)) return kLetters[k - static_cast<int>(Key::kA)];
    if (k >= static_cast<int>(Key::k0) && k <= static_cast<int>(Key::k9)) return kDigits[k - static_cast<int>(Key::k0)];
    for (const KeyName& n : kNamedKeys)
        if (n.key == key) return n.name;
    return "Unknown";
}

Key key_from_glfw(int glfw_key) {
    if (glfw_key >= GLFW_KEY_A && glfw_key <= GLFW_KEY_Z)
        return static_cast<Key>(static_cast<int>(Key::kA) + (glfw_key - GLFW_KEY_A));
    if (glfw_key >= GLFW_KEY_0 && glfw_key <= GLFW_KEY_9)
        return static_cast<Key>(static_cast<int>(Key::k0) + (glfw_key - GLFW_KEY_0));
    for (const KeyName& n : kNamedKeys)
        if (n.glfw == glfw_key) return n.key;
    return Key::kUnknown;
}

MouseButton button_from_glfw(int glfw_button) {
    switch (glfw_button) {
        case GLFW_MOUSE_BUTTON_LEFT: return MouseButton::kLeft;
        case GLFW_MOUSE_BUTTON_RIGHT: return MouseButton::kRight;
        case GLFW_MOUSE_BUTTON_MIDDLE: return MouseButton::kMiddle;
        default: return MouseButton::kOther;
    }
}

std::uint8_t modifiers_from_glfw(int glfw_mods) {
    std::uint8_t m = 0;
    if (glfw_mods & GLFW_MOD_SHIFT) m |= modifier::kShift;
    if (glfw_mods & GLFW_MOD_CONTROL) m |= modifier::kControl;
    if (glfw_mods & GLFW_MOD_ALT) m |= modifier::kAlt;
    if (glfw_mods & GLFW_MOD_SUPER) m |= modifier::kSuper;
    return m;
}

InputQueue::InputQueue(std::size_t capacity) : ring_(capacity > 0 ? capacity : 1) {}

bool InputQueue::push(const InputEvent& e) {
    if (count_ == ring_.size()) {
        ++dropped_;
        return false;
    }
    ring_[(head_ + count_) % ring_.size()] = e;
    ++count_;
    return true;
}

bool InputQueue::pop(InputEvent& e) {
    if (count_ == 0) return false;
    e = ring_[head_];
    head_ = (head_ + 1) % ring_.size();
    --count_;
    return true;
}

void InputQueue::clear() {
    head_ = 0;
    count_ = 0;
}

void InputQueue::on_key(int glfw_key, int glfw_action, int glfw_mods, double time_s) {
    InputEvent e;
    if (!action_from_glfw(glfw_action, e.action)) return;
    e.type = InputType::kKey;
    e.key = key_from_glfw(glfw_key);
    e.modifiers = modifiers_from_glfw(glfw_mods);
    e.x_px = cursor_x_;
    e.y_px = cursor_y_;
    e.time_s = time_s;
    push(e);
}

void InputQueue::on_mouse_button(int glfw_button, int glfw_action, int glfw_mods, double x_px, double y_px,
                                 double time_s) {
    InputEvent e;
    if (!action_from_glfw(glfw_action, e.action) || e.action == InputAction::kRepeat) return;
    e.type = InputType::kMouseButton;
    e.button = button_from_glfw(glfw_button);
    e.modifiers = modifiers_from_glfw(glfw_mods);
    e.x_px = x_px;
    e.y_px = y_px;
    e.time_s = time_s;
    push(e);
}

void InputQueue::on_cursor(double x_px, double y_px, double time_s) {
    const bool had = have_cursor_;
    const double dx = x_px - cursor_x_, dy = y_px - cursor_y_;
    have_cursor_ = true;
    cursor_x_ = x_px;
    cursor_y_ = y_px;
    if (had && dx == 0.0 && dy == 0.0) return;
    InputEvent e;
    e.type = InputType::kMouseMove;
    e.x_px = x_px;
    e.y_px = y_px;
    // The first position has no motion to give: NaN deltas (a view ignores them; a stylus takes the position).
    e.dx_px = had ? dx : std::numeric_limits<double>::quiet_NaN();
    e.dy_px = had ? dy : std::numeric_limits<double>::quiet_NaN();
    e.time_s = time_s;
    push(e);
}

void InputQueue::on_scroll(double dx, double dy, double x_px, double y_px, double time_s) {
    InputEvent e;
    e.type = InputType::kScroll;
    e.x_px = x_px;
    e.y_px = y_px;
    e.dx_px = dx;
    e.dy_px = dy;
    e.time_s = time_s;
    push(e);
}

}  // namespace tridex::renderer
