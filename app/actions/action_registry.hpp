// app/actions/action_registry.hpp - one list of named actions (label, glyph, what it does) that keys, the in-scene
// menu, device buttons and a bindings file all name, as Blender's operators and Vrui's tools are named.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "compute/runtime/sculpt_thread.hpp"
#include "core/tool_sample.hpp"

namespace tridex::app {

/// What an action acts on: the session's tool, model, view and life. A `tridex run` session implements it
/// (app/session/run/run_actions.hpp); tests implement it to record what was asked. One thread (the frame loop's).
class ActionTarget {
public:
    virtual ~ActionTarget() = default;
    /// The Boolean or clay operation the tool applies from now on (never ToolOp::kNone).
    virtual void set_op(ToolOp op) = 0;
    /// The operation the tool applies now.
    virtual ToolOp op() const = 0;
    /// The material (1..kMaxMaterialId, a palette entry) that union adds and paint sets from now on; the operation is
    /// kept. Ids outside the range are ignored.
    virtual void set_material(std::uint8_t id) = 0;
    /// The material union adds and paint sets now.
    virtual std::uint8_t material() const = 0;
    /// Scales the tool by a fixed step per unit (steps > 0 larger); false when it cannot change (a mesh tool, a limit).
    virtual bool resize_tool(int steps) = 0;
    /// Hands an undo, redo, save or coarseness change to the sculpt thread; false when its queue was full.
    virtual bool request(SculptRequest r) = 0;
    /// Back to the start pose and scale of the scene (and of a keyboard-and-mouse head).
    virtual void reset_scene() = 0;
    /// Exchanges the left and right eyes.
    virtual void swap_eyes() = 0;
    /// Turns the ambient occlusion on or off.
    virtual void toggle_occlusion() = 0;
    /// Turns the sculpting symmetry off, or on again (the session's own symmetry, a mirror across x when it has none).
    virtual void toggle_symmetry() = 0;
    /// Chooses the next workpiece the tool carves, in turn: automatic (the touched one, else the nearest), then the
    /// first, the second, ... and automatic again; nothing with one workpiece.
    virtual void next_workpiece() = 0;
    /// Ends the session: its outputs are written as when Esc is pressed.
    virtual void end_session() = 0;
};

/// How an action is used: once on a press (a command), or for as long as a button is held.
enum class ActionKind : std::uint8_t {
    kCommand,  ///< done once when its key, slice or button is pressed (or chosen)
    kHeld,     ///< a state held with a button: engage the tool, open the menu, grab the scene, move the workspace
    kAxis,     ///< driven by an axis in [-1, 1]: the joystick scales the scene or the tool
};

/// One named action.
struct Action {
    std::string name;   ///< unique, dotted: "op.subtract", "edit.undo", "menu"
    std::string label;  ///< what the menu's slice and the docs say: "Subtract"
    std::string glyph;  ///< a short mark drawn above the label in the menu (ASCII): "-", "+", "<<"
    ActionKind kind = ActionKind::kCommand;
    std::string doc;    ///< one line for docs/actions.md and `--help`
    /// kCommand: what it does to the target. Empty for held and axis actions, which the session's input reads.
    std::function<void(ActionTarget&)> run;
};

/// The actions by name. Thread-compatible: filled once, then read from any thread.
class ActionRegistry {
public:
    /// Adds an action; throws tridex::Error when the name is empty or taken, or a command has no `run`.
    void add(Action action);
    /// The action named `name`, or nullptr.
    const Action* find(const std::string& name) const;
    /// The action named `name`; throws tridex::Error "FIELD: unknown action 'x'; actions: a, b, ..." (FIELD =
    /// `field`, e.g. "bindings.wand.buttons.button1" in FILE) naming the closest known name when one is close.
    const Action& get(const std::string& name, const std::string& field) const;
    /// Runs a command action on `target`; returns false (doing nothing) for an unknown name or a held or axis
    /// action.
    bool run(const std::string& name, ActionTarget& target) const;
    /// Every action, in registration order.
    const std::vector<Action>& all() const { return actions_; }
    /// Every action name, comma-separated, for error texts.
    std::string names() const;

private:
    std::vector<Action> actions_;
};

/// The built-in actions: op.subtract, op.union, op.paint, op.push, op.smooth, op.pull, op.grab, op.place, op.next, material.1 ..
/// material.7 (the palette entry union adds and paint sets; the menu labels them with the session's names), tool.larger,
/// tool.smaller, symmetry.toggle, coarseness.finer, coarseness.coarser, edit.undo, edit.redo, file.save, view.reset, view.swap_eyes, view.occlusion,
/// session.end (commands);
/// engage, menu, nav.grab, workspace (held); nav.scale, tool.scale (axes).
const ActionRegistry& builtin_actions();

/// The operation after `op` in the order subtract, union, paint, push, smooth, pull (then subtract again).
ToolOp next_op(ToolOp op);

}  // namespace tridex::app
