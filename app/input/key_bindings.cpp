// app/input/key_bindings.cpp - the desk's key table.
#include "app/input/key_bindings.hpp"

namespace tridex::app {

using renderer::Key;
namespace mod = renderer::modifier;

const std::vector<KeyBinding>& desk_key_bindings() {
    static const std::vector<KeyBinding> table = {
        {Key::k1, 0, "op.subtract", false, true},
        {Key::k2, 0, "op.union", false, true},
        {Key::k3, 0, "op.paint", false, true},
        {Key::k4, 0, "op.push", false, true},
        {Key::k5, 0, "op.smooth", false, true},
        {Key::k6, 0, "op.pull", false, true},
        {Key::k7, 0, "op.grab", false, true},
        {Key::k8, 0, "op.place", false, true},
        {Key::k1, mod::kShift, "material.1", false, true},
        {Key::k2, mod::kShift, "material.2", false, true},
        {Key::k3, mod::kShift, "material.3", false, true},
        {Key::k4, mod::kShift, "material.4", false, true},
        {Key::k5, mod::kShift, "material.5", false, true},
        {Key::k6, mod::kShift, "material.6", false, true},
        {Key::k7, mod::kShift, "material.7", false, true},
        {Key::kLeftBracket, 0, "tool.smaller", false, true},
        {Key::kRightBracket, 0, "tool.larger", false, true},
        {Key::kZ, mod::kControl, "edit.undo", true, false},
        {Key::kZ, mod::kControl | mod::kShift, "edit.redo", true, false},
        {Key::kY, mod::kControl, "edit.redo", true, false},
        {Key::kS, mod::kControl, "file.save", false, false},
        {Key::kHome, 0, "view.reset", false, false},
        {Key::kTab, 0, "view.swap_eyes", false, false},
        {Key::kO, 0, "view.occlusion", false, false},
        {Key::kM, 0, "symmetry.toggle", false, false},
        {Key::kP, 0, "workpiece.next", false, false},
        {Key::kPageUp, 0, "coarseness.finer", false, false},
        {Key::kPageDown, 0, "coarseness.coarser", false, false},
        {Key::kEscape, 0, "session.end", false, false},
    };
    return table;
}

const KeyBinding* find_key_binding(Key key, std::uint8_t modifiers, bool stylus) {
    const std::uint8_t held = modifiers & (mod::kShift | mod::kControl | mod::kAlt);
    for (const KeyBinding& b : desk_key_bindings())
        if (b.key == key && b.modifiers == held && (stylus || !b.stylus_only)) return &b;
    return nullptr;
}

std::string chord_name(const KeyBinding& b) {
    std::string s;
    if (b.modifiers & mod::kControl) s += "Ctrl+";
    if (b.modifiers & mod::kAlt) s += "Alt+";
    if (b.modifiers & mod::kShift) s += "Shift+";
    return s + std::string(renderer::to_string(b.key));
}

}  // namespace tridex::app
