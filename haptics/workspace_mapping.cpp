// haptics/workspace_mapping.cpp - the four workspace techniques, one small state machine each.
#include "haptics/workspace_mapping.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace tridex::haptics {

namespace {

void require(bool ok, const char* field, double value, const char* rule) {
    if (!ok) throw Error(std::string("WorkspaceConfig.") + field + " = " + std::to_string(value) + " " + rule);
}

bool in_range(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

}  // namespace

const char* to_string(WorkspaceMode mode) {
    switch (mode) {
        case WorkspaceMode::kPengMoving: return "peng_moving";
        case WorkspaceMode::kScaling: return "scaling";
        case WorkspaceMode::kClutching: return "clutching";
        case WorkspaceMode::kBubble: return "bubble";
    }
    return "unknown";
}

WorkspaceMode parse_workspace_mode(const std::string& name) {
    for (WorkspaceMode m : {WorkspaceMode::kPengMoving, WorkspaceMode::kScaling, WorkspaceMode::kClutching,
                            WorkspaceMode::kBubble})
        if (name == to_string(m)) return m;
    throw Error("workspace mode '" + name + "' is not one of peng_moving, scaling, clutching, bubble");
}

WorkspaceMapper::WorkspaceMapper(const WorkspaceConfig& cfg, const Pose& device_to_world, double scale,
                                 const Aabb& device_workspace_m)
    : cfg_(cfg),
      rot_(device_to_world.orientation),
      scale_(scale),
      initial_offset_(device_to_world.position) {
    const int mode = static_cast<int>(cfg_.mode);
    require(mode >= 0 && mode <= 3, "mode", mode, "is not a WorkspaceMode");
    require(std::isfinite(scale) && scale > 0.0, "scale (HapticLoopConfig.workspace_scale)", scale,
            "must be finite and > 0");
    require(is_finite(initial_offset_), "device_to_world.position.x", initial_offset_.x, "(or y, z) is not finite");
    const bool needs_button = cfg_.mode == WorkspaceMode::kPengMoving || cfg_.mode == WorkspaceMode::kClutching;
    require(!needs_button || cfg_.button_mask != 0u, "button_mask", cfg_.button_mask,
            "must name at least one button for peng_moving and clutching");
    require(in_range(cfg_.jump_gain, 0.0, 10.0), "jump_gain", cfg_.jump_gain, "must be in [0, 10]");
    require(in_range(cfg_.drag_gain, 0.0, 10.0), "drag_gain", cfg_.drag_gain, "must be in [0, 10]");
    require(in_range(cfg_.bubble_rate_m_s, 0.0, 1e3), "bubble_rate_m_s", cfg_.bubble_rate_m_s,
            "must be in [0, 1000] m/s");
    require(in_range(cfg_.bubble_rate_exponent, 1.0, 5.0), "bubble_rate_exponent", cfg_.bubble_rate_exponent,
            "must be in [1, 5]");
    require(in_range(cfg_.bubble_stiffness_n_per_m, 0.0, 1e6), "bubble_stiffness_n_per_m",
            cfg_.bubble_stiffness_n_per_m, "must be in [0, 1e6] N/m");
    require(std::isfinite(cfg_.bubble_radius_m) && cfg_.bubble_radius_m >= 0.0, "bubble_radius_m",
            cfg_.bubble_radius_m, "must be finite and >= 0 (0 = default)");
    if (cfg_.mode == WorkspaceMode::kScaling) force_scale_ = 1.0 / scale_;
    if (!device_workspace_m.empty()) {
        centre_d_ = device_workspace_m.centre();
        half_d_ = 0.5 * device_workspace_m.size();
    }
    if (cfg_.bubble_radius_m == 0.0) cfg_.bubble_radius_m = 0.8 * std::min({half_d_.x, half_d_.y, half_d_.z});
    require(cfg_.mode != WorkspaceMode::kBubble || cfg_.bubble_radius_m > 0.0, "bubble_radius_m",
            cfg_.bubble_radius_m, "must be > 0 in bubble mode (the device workspace is empty; set it explicitly)");
    reset();
}

void WorkspaceMapper::reset() {
    offset_ = initial_offset_;
    was_pressed_ = false;
    press_tool_ = Vec3(0.0);
    press_box_ = Vec3(0.0);
    frozen_ = Pose{};
    frame_ = WorkspaceFrame{};
    frame_.tool_world.position = workspace_centre_m();
    frame_.tool_world.orientation = rot_;
    fill_box(workspace_centre_m());
}

void WorkspaceMapper::fill_box(const Vec3& centre_world) {
    frame_.box.position = centre_world;
    frame_.box.orientation = rot_;
    frame_.box_half_extents_m = scale_ * half_d_;
    frame_.bubble_centre_m = centre_world;
    frame_.bubble_radius_m = cfg_.mode == WorkspaceMode::kBubble ? scale_ * cfg_.bubble_radius_m : 0.0;
}

const WorkspaceFrame& WorkspaceMapper::update(const devices::DeviceState& state, double dt_s) {
    const Vec3& p = state.pose.position;
    const bool pressed = (state.buttons & cfg_.button_mask) != 0u;
    const bool press = pressed && !was_pressed_;
    const bool release = !pressed && was_pressed_;
    was_pressed_ = pressed;

    WorkspaceFrame& f = frame_;
    f.pressed = pressed;
    f.modelling_paused = false;
    f.coupled = true;
    f.mapping_changed = false;
    f.force_n = Vec3(0.0);
    f.tool_world.orientation = glm::normalize(rot_ * state.pose.orientation);
    Vec3 box_centre;

    switch (cfg_.mode) {
        case WorkspaceMode::kScaling:
            f.tool_world.position = map(p);
            box_centre = workspace_centre_m();
            break;

        case WorkspaceMode::kPengMoving: {
            const Vec3 tool = map(p);  // with the mapping in force before this tick
            if (press) {
                const Vec3 c = workspace_centre_m();
                press_tool_ = tool;
                press_box_ = c + cfg_.jump_gain * (tool - c);
            }
            if (pressed) {
                box_centre = press_box_ + cfg_.drag_gain * (tool - press_tool_);
                f.tool_world.position = tool;
                f.modelling_paused = true;
            } else if (release) {
                // The haptic workspace now coincides with the box: move the mapping by B - C.
                const Vec3 b = press_box_ + cfg_.drag_gain * (tool - press_tool_);
                offset_ += b - workspace_centre_m();
                f.tool_world.position = map(p);
                f.modelling_paused = true;  // no swept segment across the jump
                f.mapping_changed = true;
                box_centre = workspace_centre_m();
            } else {
                f.tool_world.position = tool;
                box_centre = workspace_centre_m();
            }
            break;
        }

        case WorkspaceMode::kClutching: {
            if (press) {
                frozen_.position = map(p);
                frozen_.orientation = f.tool_world.orientation;
            }
            if (pressed) {
                f.tool_world = frozen_;
                f.coupled = false;
                f.modelling_paused = true;
                // Where the workspace will be if re-clutched now.
                box_centre = frozen_.position - rot_ * (scale_ * p) + rot_ * (scale_ * centre_d_);
            } else {
                if (release) {
                    offset_ = frozen_.position - rot_ * (scale_ * p);
                    f.modelling_paused = true;
                    f.mapping_changed = true;
                }
                f.tool_world.position = map(p);
                box_centre = workspace_centre_m();
            }
            break;
        }

        case WorkspaceMode::kBubble: {
            const Vec3 d = p - centre_d_;
            const double dist = glm::length(d);
            const double rb = cfg_.bubble_radius_m;
            if (dist > rb) {
                const Vec3 out_world = rot_ * (d / dist);  // outward unit direction, world
                const double excess = dist - rb;
                if (dt_s > 0.0 && std::isfinite(dt_s)) {
                    const double speed = cfg_.bubble_rate_m_s * std::pow(excess / rb, cfg_.bubble_rate_exponent);
                    offset_ += (speed * dt_s) * out_world;
                }
                f.force_n = (-cfg_.bubble_stiffness_n_per_m * excess) * out_world;
            }
            f.tool_world.position = map(p);
            box_centre = workspace_centre_m();
            break;
        }
    }
    fill_box(box_centre);
    return f;
}

}  // namespace tridex::haptics
