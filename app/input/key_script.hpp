// app/input/key_script.hpp - key chords ("ctrl+z") by name, and a scene's timed key presses for scripted sessions.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "renderer/window/window_input.hpp"

namespace tridex::app {

/// One key chord: a key and the modifier bits (renderer::modifier) held with it.
struct KeyChord {
    renderer::Key key = renderer::Key::kUnknown;
    std::uint8_t modifiers = 0;
};

/// Parses "ctrl+shift+z", "Ctrl+S", "tab", "F1", "escape", "[" / "]" (or "leftbracket" / "rightbracket"): modifiers ctrl / control, shift, alt, super (any case,
/// any order, '+' between) and one key by its renderer::to_string name (any case; "esc" for Escape). Throws
/// tridex::Error "<where>: ..." naming the unknown part.
KeyChord parse_key_chord(const std::string& text, const std::string& where);

/// A key chord pressed at a moment of the session's device time (the haptic loop's clock, s), as a scripted
/// session's scene lists them ("keys": [{"t_s": 4.0, "press": "ctrl+z"}]), so an offscreen run exercises the same
/// key handling as a window.
struct ScriptedKey {
    double t_s = 0.0;
    KeyChord chord;
    std::string text;  ///< as written, for messages and the report
};

/// The press and release events of `chord` at `time_s` (s, the caller's clock).
std::vector<renderer::InputEvent> chord_events(const KeyChord& chord, double time_s);

}  // namespace tridex::app
