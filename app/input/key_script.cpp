// app/input/key_script.cpp - key chords by name.
#include "app/input/key_script.hpp"

#include <algorithm>
#include <cctype>

#include "core/error.hpp"

namespace tridex::app {

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

renderer::Key key_named(const std::string& name) {
    if (name == "esc") return renderer::Key::kEscape;
    if (name == "[") return renderer::Key::kLeftBracket;
    if (name == "]") return renderer::Key::kRightBracket;
    const auto last = static_cast<std::uint16_t>(renderer::Key::kKeypadSubtract);
    for (std::uint16_t k = 1; k <= last; ++k) {
        const auto key = static_cast<renderer::Key>(k);
        if (lower(std::string(renderer::to_string(key))) == name) return key;
    }
    return renderer::Key::kUnknown;
}

}  // namespace

KeyChord parse_key_chord(const std::string& text, const std::string& where) {
    KeyChord c;
    std::string rest = lower(text);
    if (rest.empty()) throw Error(where + ": an empty key chord");
    for (;;) {
        const std::size_t plus = rest.find('+');
        const std::string part = rest.substr(0, plus);
        if (plus == std::string::npos) {
            c.key = key_named(part);
            if (c.key == renderer::Key::kUnknown)
                throw Error(where + ": unknown key '" + part + "' in '" + text + "' (e.g. z, s, tab, escape, f1, left)");
            return c;
        }
        if (part == "ctrl" || part == "control") c.modifiers |= renderer::modifier::kControl;
        else if (part == "shift") c.modifiers |= renderer::modifier::kShift;
        else if (part == "alt") c.modifiers |= renderer::modifier::kAlt;
        else if (part == "super") c.modifiers |= renderer::modifier::kSuper;
        else throw Error(where + ": unknown modifier '" + part + "' in '" + text + "' (ctrl, shift, alt, super)");
        rest = rest.substr(plus + 1);
    }
}

std::vector<renderer::InputEvent> chord_events(const KeyChord& chord, double time_s) {
    renderer::InputEvent e;
    e.type = renderer::InputType::kKey;
    e.key = chord.key;
    e.modifiers = chord.modifiers;
    e.time_s = time_s;
    e.action = renderer::InputAction::kPress;
    renderer::InputEvent up = e;
    up.action = renderer::InputAction::kRelease;
    return {e, up};
}

}  // namespace tridex::app
