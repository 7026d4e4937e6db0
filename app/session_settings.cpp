// app/session_settings.cpp - session settings: device profile, loop configuration, JSON.
#include "app/session_settings.hpp"

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "devices/device_profiles.hpp"
#include "haptics/tool_points.hpp"
#include "haptics/workspace_mapping.hpp"

namespace tridex::app {

devices::DeviceProfile device_profile(const std::string& name) {
    if (name == "omni") return devices::DeviceProfile::phantom_omni();
    if (name == "wand") return devices::quanser_wand_5dof();
    if (name == "6dof") return devices::generic_6dof();
    throw Error("--device: unknown device '" + name + "'; use omni, wand or 6dof");
}

ToolOp parse_tool_op(const std::string& name) {
    if (name == "subtract") return ToolOp::kSubtract;
    if (name == "union") return ToolOp::kUnion;
    if (name == "paint") return ToolOp::kPaint;
    throw Error("--op: unknown operation '" + name + "'; use subtract, union or paint");
}

haptics::HapticLoopConfig loop_config(const SessionSettings& s, std::size_t max_ticks) {
    if (s.material < 1 || s.material > 7)
        throw Error("--material: must be a palette id between 1 and 7, got " + std::to_string(s.material));
    if (s.points < 1 || s.points > haptics::kMaxToolPoints)
        throw Error("--points: must be between 1 and " + std::to_string(haptics::kMaxToolPoints) + ", got " +
                    std::to_string(s.points));
    if (!(s.static_friction >= 0.0 && s.dynamic_friction >= 0.0 && s.dynamic_friction <= s.static_friction))
        throw Error("--friction: need 0 <= dynamic <= static, got static " + std::to_string(s.static_friction) +
                    ", dynamic " + std::to_string(s.dynamic_friction));
    haptics::HapticLoopConfig cfg;
    cfg.period_s = s.period_s;
    cfg.contact.stiffness_n_per_m = s.stiffness_n_per_m;
    cfg.contact.damping_n_s_per_m = s.damping_n_s_per_m;
    cfg.contact.tool_radius_m = s.tool_radius_m;
    cfg.contact.static_friction = s.static_friction;
    cfg.contact.dynamic_friction = s.dynamic_friction;
    cfg.contact.cutting = s.cutting && parse_tool_op(s.op) == ToolOp::kSubtract;  // only removal resists
    cfg.device_to_world.position = s.device_origin_m;
    cfg.workspace_scale = s.workspace_scale;
    cfg.workspace.mode = haptics::parse_workspace_mode(s.workspace_mode);
    cfg.op = parse_tool_op(s.op);
    cfg.material = static_cast<std::uint8_t>(s.material);
    cfg.max_ticks = max_ticks;
    if (s.points == 1) {
        cfg.tool_points = haptics::ToolPoints::single(s.tool_radius_m);
    } else if (s.points == 2) {
        cfg.tool_points = haptics::ToolPoints::wand(s.wand_half_length_m);
        cfg.tool_points.radius_m = s.tool_radius_m;
    } else {
        cfg.tool_points = haptics::ToolPoints::sphere_mesh(s.tool_radius_m, s.points);
        cfg.contact_mode = haptics::MultiPointMode::kInteractionMesh;
    }
    return cfg;
}

namespace {

nlohmann::json vec(const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

}  // namespace

std::string settings_to_json(const SessionSettings& s) {
    const nlohmann::json j{{"mesh_path", s.mesh_path},
                           {"resolution", s.resolution},
                           {"stock_m", s.stock_m},
                           {"workpiece_centre_m", vec(s.workpiece_centre_m)},
                           {"tool_radius_m", s.tool_radius_m},
                           {"points", s.points},
                           {"wand_half_length_m", s.wand_half_length_m},
                           {"device", s.device},
                           {"workspace_mode", s.workspace_mode},
                           {"workspace_scale", s.workspace_scale},
                           {"device_origin_m", vec(s.device_origin_m)},
                           {"stiffness_n_per_m", s.stiffness_n_per_m},
                           {"damping_n_s_per_m", s.damping_n_s_per_m},
                           {"static_friction", s.static_friction},
                           {"dynamic_friction", s.dynamic_friction},
                           {"cutting", s.cutting},
                           {"op", s.op},
                           {"material", s.material},
                           {"period_s", s.period_s}};
    return j.dump();
}

SessionSettings settings_from_json(const std::string& text, const std::string& source) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        throw Error(source + ": settings are not JSON: " + e.what());
    }
    auto field = [&](const char* name) -> const nlohmann::json& {
        if (!j.is_object() || !j.contains(name)) throw Error(source + ": settings field '" + name + "' is missing");
        return j.at(name);
    };
    auto get = [&](const char* name, auto& out) {
        try {
            field(name).get_to(out);
        } catch (const nlohmann::json::exception&) {
            throw Error(source + ": settings field '" + name + "' has the wrong type");
        }
    };
    auto get_vec = [&](const char* name, Vec3& out) {
        const auto& a = field(name);
        if (!a.is_array() || a.size() != 3 || !a[0].is_number() || !a[1].is_number() || !a[2].is_number())
            throw Error(source + ": settings field '" + name + "' must be [x, y, z]");
        out = Vec3(a[0].get<double>(), a[1].get<double>(), a[2].get<double>());
    };
    SessionSettings s;
    get("mesh_path", s.mesh_path);
    get("resolution", s.resolution);
    get("stock_m", s.stock_m);
    get_vec("workpiece_centre_m", s.workpiece_centre_m);
    get("tool_radius_m", s.tool_radius_m);
    get("points", s.points);
    get("wand_half_length_m", s.wand_half_length_m);
    get("device", s.device);
    get("workspace_mode", s.workspace_mode);
    get("workspace_scale", s.workspace_scale);
    get_vec("device_origin_m", s.device_origin_m);
    get("stiffness_n_per_m", s.stiffness_n_per_m);
    get("damping_n_s_per_m", s.damping_n_s_per_m);
    get("static_friction", s.static_friction);
    get("dynamic_friction", s.dynamic_friction);
    get("cutting", s.cutting);
    get("period_s", s.period_s);
    // Added later: recordings made before them sculpted with subtract.
    if (j.contains("op")) get("op", s.op);
    if (j.contains("material")) get("material", s.material);
    return s;
}

}  // namespace tridex::app
