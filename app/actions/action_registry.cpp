// app/actions/action_registry.cpp - the built-in actions and their lookup.
#include "app/actions/action_registry.hpp"

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <utility>

#include "core/error.hpp"
#include "core/text/nearest_name.hpp"

namespace tridex::app {

namespace {

Action command(std::string name, std::string label, std::string glyph, std::string doc,
               std::function<void(ActionTarget&)> run) {
    return Action{std::move(name), std::move(label), std::move(glyph), ActionKind::kCommand, std::move(doc),
                  std::move(run)};
}

Action held(std::string name, std::string label, std::string doc, ActionKind kind = ActionKind::kHeld) {
    return Action{std::move(name), std::move(label), "", kind, std::move(doc), {}};
}

ActionRegistry make_builtin() {
    ActionRegistry r;
    const auto op = [](ToolOp o) { return [o](ActionTarget& t) { t.set_op(o); }; };
    r.add(command("op.subtract", "Subtract", "-", "carve: the tool's swept volume is removed", op(ToolOp::kSubtract)));
    r.add(command("op.union", "Union", "+", "add: the tool's swept volume becomes material", op(ToolOp::kUnion)));
    r.add(command("op.paint", "Paint", "*", "paint the touched surface with the tool's material", op(ToolOp::kPaint)));
    r.add(command("op.push", "Push", "v", "clay: dent the pressed surface, its volume back as a rim", op(ToolOp::kPush)));
    r.add(command("op.smooth", "Smooth", "~", "clay: relax the surface under the tool", op(ToolOp::kSmooth)));
    r.add(command("op.pull", "Pull", "^", "clay: the touched surface follows the tool outward", op(ToolOp::kPull)));
    r.add(command("op.grab", "Grab", "&", "clay: the material near the touched point moves with the tool",
                  op(ToolOp::kGrab)));
    r.add(command("op.place", "Place", "@", "the whole workpiece follows the tool while it is engaged: move and turn it",
                  op(ToolOp::kPlace)));
    r.add(command("op.next", "Next op", ">", "the next sculpting operation (subtract, union, paint, push, smooth, pull, grab)",
                  [](ActionTarget& t) { t.set_op(next_op(t.op())); }));
    for (int m = 1; m <= kMaxMaterialId; ++m) {
        const auto id = static_cast<std::uint8_t>(m);
        r.add(command("material." + std::to_string(m), "Material " + std::to_string(m), std::to_string(m),
                      "union adds and paint sets palette material " + std::to_string(m) + " from now on",
                      [id](ActionTarget& t) { t.set_material(id); }));
    }
    r.add(command("tool.larger", "Larger", "O", "the tool 1.25 times larger",
                  [](ActionTarget& t) { (void)t.resize_tool(1); }));
    r.add(command("tool.smaller", "Smaller", "o", "the tool 1.25 times smaller",
                  [](ActionTarget& t) { (void)t.resize_tool(-1); }));
    r.add(command("symmetry.toggle", "Symmetry", "|", "sculpting symmetry off, or on again (mirror or radial copies)",
                  [](ActionTarget& t) { t.toggle_symmetry(); }));
    r.add(command("workpiece.next", "Workpiece", "#",
                  "the workpiece the tool carves: automatic (the touched or nearest), then each in turn",
                  [](ActionTarget& t) { t.next_workpiece(); }));
    r.add(command("coarseness.finer", "Finer", "N*2",
                  "the model re-sampled onto a lattice of twice the resolution (one undo step)",
                  [](ActionTarget& t) { (void)t.request(SculptRequest::kFiner); }));
    r.add(command("coarseness.coarser", "Coarser", "N/2",
                  "the model re-sampled onto a lattice of half the resolution (one undo step)",
                  [](ActionTarget& t) { (void)t.request(SculptRequest::kCoarser); }));
    r.add(command("edit.undo", "Undo", "<", "undo the newest stroke",
                  [](ActionTarget& t) { (void)t.request(SculptRequest::kUndo); }));
    r.add(command("edit.redo", "Redo", ">", "redo the newest undone stroke",
                  [](ActionTarget& t) { (void)t.request(SculptRequest::kRedo); }));
    r.add(command("file.save", "Save", "S", "save the model now (--save FILE.tdx, else OUT/model.tdx)",
                  [](ActionTarget& t) { (void)t.request(SculptRequest::kSave); }));
    r.add(command("view.reset", "Re-centre", "@", "the scene (and a keyboard head) back to where it started",
                  [](ActionTarget& t) { t.reset_scene(); }));
    r.add(command("view.swap_eyes", "Swap eyes", "<>", "exchange the left and right eyes",
                  [](ActionTarget& t) { t.swap_eyes(); }));
    r.add(command("view.occlusion", "Occlusion", "AO", "ambient occlusion on or off",
                  [](ActionTarget& t) { t.toggle_occlusion(); }));
    r.add(command("session.end", "End session", "X", "end the session; its outputs are written",
                  [](ActionTarget& t) { t.end_session(); }));
    r.add(held("engage", "Engage", "held: the tool carves (a device without an engage button always carves)"));
    r.add(held("menu", "Menu", "held: the pie menu opens at the hand; release over a slice (or flick) to choose"));
    r.add(held("nav.grab", "Grab scene", "held: the scene follows the wand rigidly"));
    r.add(held("workspace", "Workspace", "held: the stylus button of the workspace techniques (move, clutch)"));
    r.add(held("nav.scale", "Scale scene", "axis: scales the scene about its pivot (doubles in 1 s at full tilt)",
               ActionKind::kAxis));
    r.add(held("tool.scale", "Scale tool", "axis: tilted past half way, the tool grows or shrinks a step every 0.4 s",
               ActionKind::kAxis));
    return r;
}

}  // namespace

void ActionRegistry::add(Action action) {
    if (action.name.empty()) throw Error("ActionRegistry::add: an action needs a name");
    if (find(action.name)) throw Error("ActionRegistry::add: the action '" + action.name + "' exists already");
    if (action.kind == ActionKind::kCommand && !action.run)
        throw Error("ActionRegistry::add: the command '" + action.name + "' does nothing");
    actions_.push_back(std::move(action));
}

const Action* ActionRegistry::find(const std::string& name) const {
    const auto it = std::find_if(actions_.begin(), actions_.end(), [&](const Action& a) { return a.name == name; });
    return it == actions_.end() ? nullptr : &*it;
}

const Action& ActionRegistry::get(const std::string& name, const std::string& field) const {
    if (const Action* a = find(name)) return *a;
    std::vector<std::string> known;
    for (const Action& a : actions_) known.push_back(a.name);
    const std::string best = nearest_name(name, known);
    throw Error(field + ": unknown action '" + name + "'" + (best.empty() ? "" : " (did you mean '" + best + "'?)") +
                "; actions: " + names());
}

bool ActionRegistry::run(const std::string& name, ActionTarget& target) const {
    const Action* a = find(name);
    if (!a || a->kind != ActionKind::kCommand) return false;
    a->run(target);
    return true;
}

std::string ActionRegistry::names() const {
    std::string out;
    for (const Action& a : actions_) out += (out.empty() ? "" : ", ") + a.name;
    return out;
}

const ActionRegistry& builtin_actions() {
    static const ActionRegistry registry = make_builtin();
    return registry;
}

ToolOp next_op(ToolOp op) {
    static constexpr ToolOp kCycle[] = {ToolOp::kSubtract, ToolOp::kUnion, ToolOp::kPaint,
                                        ToolOp::kPush,     ToolOp::kSmooth, ToolOp::kPull, ToolOp::kGrab};
    const auto* it = std::find(std::begin(kCycle), std::end(kCycle), op);
    if (it == std::end(kCycle)) return ToolOp::kSubtract;
    ++it;
    return it == std::end(kCycle) ? kCycle[0] : *it;
}

}  // namespace tridex::app
