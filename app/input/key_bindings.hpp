// app/input/key_bindings.hpp - the desk's keys as names of actions (app/actions/action_registry.hpp): one table that
// the window's input handler, `--help` and docs/desk.md read.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "renderer/window/window_input.hpp"

namespace tridex::app {

/// One key chord bound to an action.
struct KeyBinding {
    renderer::Key key = renderer::Key::kUnknown;
    std::uint8_t modifiers = 0;  ///< renderer::modifier bits that must be held (exactly)
    std::string action;          ///< an action name of builtin_actions()
    bool repeats = false;        ///< the key's auto-repeat does it again (Ctrl+Z held undoes stroke after stroke)
    bool stylus_only = false;    ///< only while the mouse is the stylus (digits and brackets move nothing else)
};

/// The desk's key chords: 1..6 operations, Shift+1..Shift+7 the material (palette entry) union adds and paint sets,
/// [ and ] tool size, Ctrl+Z undo, Ctrl+Shift+Z and Ctrl+Y redo, Ctrl+S save,
/// Home re-centre, Tab swap eyes, O occlusion, Esc end. Head keys (W A S D R F, arrows) are navigation, not actions.
const std::vector<KeyBinding>& desk_key_bindings();

/// The binding of `key` with `modifiers` held (the modifier keys themselves ignored), or nullptr. `stylus`: the
/// mouse is the stylus (stylus_only bindings count).
const KeyBinding* find_key_binding(renderer::Key key, std::uint8_t modifiers, bool stylus);

/// "Ctrl+Shift+Z", "Home", "1": a chord as docs and the overlay write it.
std::string chord_name(const KeyBinding& b);

}  // namespace tridex::app
