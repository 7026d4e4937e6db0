// renderer/window/window_input.hpp - keyboard and mouse input as plain, window-system-free events.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace tridex::renderer {

/// Keys the head and scene controls may bind (a window-system-independent subset).
enum class Key : std::uint16_t {
    kUnknown = 0,
    kA, kB, kC, kD, kE, kF, kG, kH, kI, kJ, kK, kL, kM, kN, kO, kP, kQ, kR, kS, kT, kU, kV, kW, kX, kY, kZ,
    k0, k1, k2, k3, k4, k5, k6, k7, k8, k9,
    kSpace, kEscape, kEnter, kTab, kBackspace,
    kLeft, kRight, kUp, kDown, kPageUp, kPageDown, kHome, kEnd, kInsert, kDelete,
    kLeftShift, kRightShift, kLeftControl, kRightControl, kLeftAlt, kRightAlt,
    kF1, kF2, kF3, kF4, kF5, kF6, kF7, kF8, kF9, kF10, kF11, kF12,
    kMinus, kEqual, kComma, kPeriod, kLeftBracket, kRightBracket, kKeypadAdd, kKeypadSubtract,
};

/// Short name of a key ("A", "0", "Space", "Left", "F1", ...; "Unknown").
std::string_view to_string(Key key);

/// Mouse buttons.
enum class MouseButton : std::uint8_t { kLeft, kRight, kMiddle, kOther };

/// Press, release or auto-repeat of a key or button (buttons never repeat).
enum class InputAction : std::uint8_t { kPress, kRelease, kRepeat };

/// Modifier bits held during an event (InputEvent::modifiers).
namespace modifier {
inline constexpr std::uint8_t kShift = 1, kControl = 2, kAlt = 4, kSuper = 8;
}

/// What an InputEvent is.
enum class InputType : std::uint8_t {
    kKey,          ///< key, action, modifiers
    kMouseButton,  ///< button, action, modifiers, x_px/y_px = cursor position
    kMouseMove,    ///< dx_px/dy_px = cursor motion since the previous position (x right, y down; NaN for the first position), x_px/y_px = new position
    kScroll,       ///< dx_px/dy_px = scroll offsets (wheel steps; +dy = away from the user)
};

/// One input event, window-system free. Fields not listed for the type are zero / defaults.
struct InputEvent {
    InputType type = InputType::kKey;
    InputAction action = InputAction::kPress;
    Key key = Key::kUnknown;
    MouseButton button = MouseButton::kLeft;
    std::uint8_t modifiers = 0;  ///< modifier:: bits
    double x_px = 0, y_px = 0;   ///< cursor position in window coordinates (pixels from the top-left)
    double dx_px = 0, dy_px = 0; ///< motion (kMouseMove, pixels) or scroll offsets (kScroll, steps)
    double time_s = 0;           ///< when it happened, seconds on the caller's clock (glfwGetTime for windows)
};

/// A fixed-capacity FIFO of InputEvents (storage allocated once, at construction), filled by the window's
/// callbacks through the on_*() translators and drained by the app, which hands the events to the head
/// and scene controls. When full, new events are dropped and counted (dropped()). Not thread-safe: the
/// window system delivers events on the thread that polls them, and the same thread drains the queue.
class InputQueue {
public:
    /// A queue holding up to `capacity` events (>= 1; 0 is raised to 1).
    explicit InputQueue(std::size_t capacity = 1024);

    /// Appends `e`; returns false (and counts a drop) when the queue is full.
    bool push(const InputEvent& e);
    /// Removes the oldest event into `e`; false when empty.
    bool pop(InputEvent& e);
    std::size_t size() const { return count_; }          ///< events waiting
    std::size_t capacity() const { return ring_.size(); }  ///< maximum events waiting
    std::uint64_t dropped() const { return dropped_; }     ///< events lost to a full queue since construction
    /// Discards the waiting events (the drop counter stays).
    void clear();

    // Translators from GLFW's callback arguments (GLFW key/button/action/modifier codes) to InputEvents.
    // The window's callbacks forward to these; they are public so that they can be tested without a display.

    /// A key callback: unmapped keys become Key::kUnknown; unknown actions are ignored.
    void on_key(int glfw_key, int glfw_action, int glfw_mods, double time_s);
    /// A mouse button callback at cursor position (x_px, y_px).
    void on_mouse_button(int glfw_button, int glfw_action, int glfw_mods, double x_px, double y_px, double time_s);
    /// A cursor position callback: pushes kMouseMove with the new position and the delta from the last one
    /// (none when it is zero); the first position after construction or reset_cursor() has NaN deltas (a delta
    /// from nowhere would jump the view; the position still places a stylus).
    void on_cursor(double x_px, double y_px, double time_s);
    /// A scroll callback with offsets (dx, dy) in wheel steps.
    void on_scroll(double dx, double dy, double x_px, double y_px, double time_s);
    /// Forgets the last cursor position (call when the cursor leaves / re-enters the window or focus changes).
    void reset_cursor() { have_cursor_ = false; }
    double cursor_x() const { return cursor_x_; }  ///< last cursor position, pixels
    double cursor_y() const { return cursor_y_; }  ///< last cursor position, pixels

private:
    std::vector<InputEvent> ring_;
    std::size_t head_ = 0, count_ = 0;
    std::uint64_t dropped_ = 0;
    bool have_cursor_ = false;
    double cursor_x_ = 0, cursor_y_ = 0;
};

/// The Key for a GLFW key code (GLFW_KEY_*); Key::kUnknown when it has no counterpart.
Key key_from_glfw(int glfw_key);
/// The MouseButton for a GLFW button code (GLFW_MOUSE_BUTTON_*).
MouseButton button_from_glfw(int glfw_button);
/// modifier:: bits from GLFW_MOD_* bits.
std::uint8_t modifiers_from_glfw(int glfw_mods);

}  // namespace tridex::renderer
