// haptics/haptic_loop_tool.cpp - the haptic loop's tool, operation, symmetry and menu: set from other threads
// (lock-free: atomics and triple buffers) and taken up by the loop at its next tick; and the tool placing the
// target workpiece (ToolOp::kPlace).
#include "haptics/haptic_loop.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace tridex::haptics {

void HapticLoop::set_tool_op(ToolOp op, std::uint8_t material) {
    op_.store(static_cast<std::uint16_t>(static_cast<std::uint16_t>(op) | (material << 8)), std::memory_order_relaxed);
}

void HapticLoop::set_symmetry(const Symmetry& s) {
    if (!valid_symmetry(s)) throw Error("haptic loop: not a valid symmetry (" + to_string(s) + ")");
    symmetry_.store(symmetry_bits(s), std::memory_order_relaxed);
}

bool HapticLoop::tool_change_allowed(const ToolShape& tool) const {
    if (tool.kind != cfg_.tool.kind || tool.kind == ToolKind::kMesh || !(cfg_.tool.radius_m > 0.0)) return false;
    if (!(std::isfinite(tool.radius_m) && tool.radius_m > 0.0) || !std::isfinite(tool.length_m)) return false;
    return tool.kind != ToolKind::kFlatEnd || tool.length_m > 0.0;
}

bool HapticLoop::set_tool(const ToolShape& tool) {
    if (!tool_change_allowed(tool)) return false;
    ToolUpdate& u = tool_updates_.back();
    u.serial = ++tool_serial_sent_;
    u.tool = tool;
    tool_updates_.publish();
    return true;
}

void HapticLoop::set_menu(const MenuDetent& m) {
    if (m.open) check_menu_detent(m, stiffness_cap_n_per_m_);
    menu_updates_.back() = m;
    menu_updates_.publish();
}

void HapticLoop::use_tool(const ToolShape& tool) {
    const double s = tool.radius_m / cfg_.tool.radius_m;
    const ToolPoints scaled = base_points_.scaled(s);
    bool all = true;  // every workpiece's contact takes the same points, or none does
    for (const std::unique_ptr<Piece>& p : pieces_) all = p->contact->set_points(scaled) && all;
    if (all) {
        tool_ = tool;
        device_.observe_tool_scale(s);  // a contact loop next to the device touches with the same tool
    }
    reset_contact();
}

void HapticLoop::apply_tool_changes(double device_t_s) {
    const ToolUpdate& u = tool_updates_.latest();
    if (u.serial != tool_serial_used_) {
        tool_serial_used_ = u.serial;
        use_tool(u.tool);
    }
    const std::vector<ToolChange>& sched = cfg_.tool_schedule;
    for (; next_change_ < sched.size() && sched[next_change_].device_t_s <= device_t_s; ++next_change_) {
        const ToolChange& c = sched[next_change_];
        set_tool_op(c.op, c.material);
        symmetry_.store(symmetry_bits(c.symmetry), std::memory_order_relaxed);
        // A replay's target: taken at once, even within a stroke (the recorded tick carved it, whatever this replay's
        // contacts say).
        if (c.workpiece >= 0 && choose_workpiece(c.workpiece)) target_held_ = false;
        if (tool_change_allowed(c.tool) && (c.tool.radius_m != tool_.radius_m || c.tool.length_m != tool_.length_m))
            use_tool(c.tool);
    }
}

bool HapticLoop::place(bool engaged, const Pose& tool_world) {
    Piece& held = *pieces_[target_];  // the target does not change while placing (pick_target)
    if (!engaged || !is_finite(tool_world.position)) {
        const Pose& now = held.world_from_model;
        if (placing_ && (now.position != grip_before_.position || now.orientation != grip_before_.orientation))
            placement_ = Placement{placement_.serial + 1, static_cast<std::uint8_t>(target_), grip_before_, now,
                                   held.pushed};
        placing_ = false;
        return false;
    }
    if (!placing_) {  // the grip: where the workpiece sits in the tool's frame, kept while the tool holds it
        grip_before_ = held.world_from_model;
        grip_ = tool_world.inverse() * held.world_from_model;
        placing_ = true;
        reset_contact();
    }
    held.world_from_model = tool_world * grip_;
    held.model_from_world = held.world_from_model.inverse();
    return true;
}

}  // namespace tridex::haptics
