// app/scene/session_spec.cpp - the session spec: device profile, loop configuration, JSON.
#include "app/scene/session_spec.hpp"
#include "app/scene/workpiece_list.hpp"

#include "devices/mouse_device.hpp"
#include "devices/tracking/tracked_tool_device.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <tuple>

#include <nlohmann/json.hpp>

#include "core/crc32.hpp"
#include "app/scene/tool_mesh.hpp"
#include "core/error.hpp"
#include "devices/net/net_device.hpp"
#include "core/format.hpp"
#include "app/input/glfw_device_host.hpp"
#include "devices/device_profiles.hpp"
#include "devices/registry/device_registry.hpp"
#include "haptics/tool_points.hpp"
#include "haptics/workspace_mapping.hpp"

namespace tridex::app {

const devices::DriverCapabilities& driver_caps(const std::string& driver) {
    return devices::builtin_registry().info(driver).caps;
}

std::uint32_t engage_mask_for(const std::string& driver) {
    const int button = driver_caps(driver).engage_button;
    return button >= 0 && button < 32 ? 1u << button : 0u;
}

devices::DeviceProfile device_profile(const std::string& name) {
    try {
        return devices::profile_by_name(name);
    } catch (const Error&) {
        throw Error("--device: unknown device '" + name + "'; use omni, wand, 6dof, falcon, falcon-emulator or net:HOST:PORT");
    }
}

std::unique_ptr<devices::HapticDevice> make_device(const SessionSpec& s, const devices::DeviceInputs& inputs) {
    devices::DeviceSpec d;
    d.driver = s.device_driver;
    d.profile = s.device;
    d.serial = s.device_serial;
    devices::DeviceInputs in = inputs;
    if (!s.device_firmware.empty()) in.firmware = s.device_firmware;
    if (!s.device_key_file.empty()) in.key_file = s.device_key_file;
    if (!s.device_passphrase_env.empty()) in.passphrase_env = s.device_passphrase_env;
    if (!in.host) in.host = &glfw_device_host();  // the window system's input (game controllers)
    in.haptic_rendering = s.haptic_rendering;
    return devices::builtin_registry().create(d, in);
}

void configure_net_device(devices::HapticDevice& device, const haptics::HapticLoopConfig& cfg) {
    auto* net = dynamic_cast<devices::net::NetDevice*>(&device);
    if (!net || net->mode() != devices::net::RenderingMode::kLocal) return;
    devices::net::ContactMsg c;
    c.stiffness_n_per_m = cfg.contact.stiffness_n_per_m;
    c.damping_n_s_per_m = cfg.contact.damping_n_s_per_m;
    c.tool_radius_m = cfg.contact.tool_radius_m;
    c.static_friction = cfg.contact.static_friction;
    c.dynamic_friction = cfg.contact.dynamic_friction;
    c.ewma_alpha = cfg.ewma_alpha;
    // The server's loop renders against the workpiece's surface, in its model frame: its world is that frame.
    c.device_to_world = cfg.workpiece_pose.inverse() * cfg.device_to_world;
    c.workspace_scale = cfg.workspace_scale;
    const haptics::WorkspaceConfig& w = cfg.workspace;
    c.workspace_mode = static_cast<std::uint8_t>(w.mode);
    c.button_mask = w.button_mask;
    c.jump_gain = w.jump_gain;
    c.drag_gain = w.drag_gain;
    c.bubble_radius_m = w.bubble_radius_m;
    c.bubble_rate_m_s = w.bubble_rate_m_s;
    c.bubble_rate_exponent = w.bubble_rate_exponent;
    c.bubble_stiffness_n_per_m = w.bubble_stiffness_n_per_m;
    // The same contact points as this session's own loop would render with.
    static_assert(devices::net::kMaxContactPoints == haptics::kMaxToolPoints);
    const haptics::ToolPoints& tp = cfg.tool_points;
    c.point_count = static_cast<std::uint8_t>(std::clamp(tp.count, 0, haptics::kMaxToolPoints));
    c.point_radius_m = tp.radius_m;
    c.point_local_m = tp.local_m;
    c.point_normal = tp.normal;
    net->set_contact(c);
}

ToolOp parse_tool_op(const std::string& name) {
    if (name == "subtract") return ToolOp::kSubtract;
    if (name == "union") return ToolOp::kUnion;
    if (name == "paint") return ToolOp::kPaint;
    if (name == "push") return ToolOp::kPush;
    if (name == "smooth") return ToolOp::kSmooth;
    if (name == "pull") return ToolOp::kPull;
    if (name == "grab") return ToolOp::kGrab;
    if (name == "place") return ToolOp::kPlace;
    if (name == "none") return ToolOp::kNone;
    throw Error("--op: unknown operation '" + name +
                "'; use subtract, union, paint, push, smooth, pull, grab, place or none");
}

namespace {

double bounding_radius_m(const TriMesh& m) {
    double r = 0.0;
    for (const Vec3& p : m.positions) r = std::max(r, glm::length(p));
    return r;
}

}  // namespace

void set_tool_mesh(SessionSpec& s, const std::string& path, double size_m, const std::string& what) {
    try {
        const std::string abs = std::filesystem::absolute(path).lexically_normal().string();
        const std::shared_ptr<const compute::MeshTool> tool = make_session_mesh_tool(abs, size_m);
        s.tool = ToolShape{ToolKind::kMesh, tool->bounding_radius_m(), 0.0, 0};
        s.tool_mesh_path = abs;  // a recording replays from any folder
        s.tool_size_m = size_m;
        std::tie(s.tool_mesh_crc32, s.tool_mesh_bytes) = file_crc32(abs);
    } catch (const Error& e) {
        throw Error(what + ": " + e.what());
    }
}

haptics::HapticLoopConfig loop_config(const SessionSpec& s, std::size_t max_ticks, const TriMesh* tool_mesh_m) {
    if (s.material < 1 || s.material > 7)
        throw Error("--material: must be a palette id between 1 and 7, got " + std::to_string(s.material));
    // The scene's range for the same coefficients (haptics.static_friction, [0, 10]).
    if (!(s.static_friction >= 0.0 && s.dynamic_friction >= 0.0 && s.dynamic_friction <= s.static_friction &&
          s.static_friction <= 10.0))
        throw Error("static_friction, dynamic_friction: need 0 <= dynamic <= static <= 10, got static " +
                    format_number(s.static_friction) + ", dynamic " + format_number(s.dynamic_friction));
    std::shared_ptr<const compute::MeshTool> loaded;  // kMesh without a mesh given: its file, loaded again
    ToolShape tool = s.tool;
    if (s.tool.kind == ToolKind::kMesh) {
        if (!tool_mesh_m) {
            if (s.tool_mesh_path.empty()) throw Error("tool.mesh: a mesh tool needs its mesh file");
            loaded = make_session_mesh_tool(s.tool_mesh_path, s.tool_size_m);
            tool_mesh_m = &loaded->mesh();
        }
        tool.radius_m = bounding_radius_m(*tool_mesh_m);
        tool.length_m = 0.0;
        tool.mesh_id = 0;
    }
    haptics::HapticLoopConfig cfg;
    cfg.period_s = s.period_s;
    cfg.contact.stiffness_n_per_m = s.stiffness_n_per_m;
    cfg.contact.damping_n_s_per_m = s.damping_n_s_per_m;
    cfg.contact.tool_radius_m = tool.radius_m;
    cfg.contact.static_friction = s.static_friction;
    cfg.contact.dynamic_friction = s.dynamic_friction;
    cfg.contact.cutting = s.cutting && parse_tool_op(s.op) == ToolOp::kSubtract;  // only removal resists
    if (!s.materials.empty()) {
        auto table = std::make_shared<haptics::MaterialTable>(haptics::Material{
            s.stiffness_n_per_m, s.damping_n_s_per_m, s.static_friction, s.dynamic_friction});
        for (std::size_t i = 0; i < s.materials.size(); ++i) {
            const MaterialEntry& m = s.materials[i];
            const std::string where = "materials[" + std::to_string(i) + "]";
            if (m.id < 0 || m.id > 255) throw Error(where + ".id: must be 0..255, got " + std::to_string(m.id));
            table->set(m.id, m.material);
        }
        cfg.contact.materials = std::move(table);
    }
    cfg.device_to_world.position = s.device_origin_m;
    cfg.workspace_scale = s.workspace_scale;
    cfg.workspace.mode = haptics::parse_workspace_mode(s.workspace_mode);
    cfg.op = parse_tool_op(s.op);
    cfg.engage_mask = engage_mask_for(s.device_driver);  // carve while the left button or the trigger is held
    cfg.material = static_cast<std::uint8_t>(s.material);
    cfg.symmetry = parse_symmetry(s.symmetry, "--symmetry");
    cfg.max_ticks = max_ticks;
    cfg.tool = tool;
    cfg.tool_points = haptics::tool_points_for(tool, s.points, "tool", tool_mesh_m);
    cfg.contact_mode = cfg.tool_points.count > 2 ? haptics::MultiPointMode::kInteractionMesh
                                                 : haptics::MultiPointMode::kIndependentProxies;
    cfg.elastic_objects = s.elastic_objects;
    cfg.workpiece_pose = workpiece_pose(s);
    cfg.reserve_cpu = s.reserve_haptic_cpu;
    return cfg;
}

Pose workpiece_pose(const SessionSpec& s) {
    const Vec3& c = s.workpiece_centre_m;
    return Pose{c + s.workpiece_shift_m - s.workpiece_turn * c, s.workpiece_turn};
}

namespace {

using nlohmann::json;

json vec(const Vec3& v) { return json::array({v.x, v.y, v.z}); }

}  // namespace

void validate_spec(const SessionSpec& s, const std::string& source) {
    auto fail = [&](const std::string& field, const std::string& rule, const std::string& got) {
        throw Error(source + ": settings field '" + field + "': " + rule + ", got " + got);
    };
    auto range = [&](const std::string& field, double v, double lo, double hi, bool lo_open = false) {
        if (!std::isfinite(v) || v > hi || (lo_open ? v <= lo : v < lo))
            fail(field, "must be in " + std::string(lo_open ? "(" : "[") + format_number(lo) + ", " + format_number(hi) + "]", format_number(v));
    };
    auto point = [&](const std::string& field, const Vec3& p) {
        for (int a = 0; a < 3; ++a) range(field + "[" + std::to_string(a) + "]", p[a], -1e3, 1e3);
    };
    if (const std::string why = palette_problem(s.palette); !why.empty()) fail("palette", why, "a palette");
    if (s.resolution < 8 || s.resolution > 4096) fail("resolution", "must be between 8 and 4096", std::to_string(s.resolution));
    range("stock_m", s.stock_m, 1e-3, 100.0);
    point("workpiece_centre_m", s.workpiece_centre_m);
    point("workpiece_shift_m", s.workpiece_shift_m);
    {
        const Quat& q = s.workpiece_turn;
        const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
        if (!(std::abs(n - 1.0) <= 1e-6)) fail("workpiece_turn", "must be a unit quaternion [w, x, y, z]", format_number(n));
    }
    point("device_origin_m", s.device_origin_m);
    if (s.tool.kind == ToolKind::kMesh) {
        range("tool.size_m", s.tool_size_m, 1e-3, 0.25 * s.stock_m);
        range("tool.radius_m", s.tool.radius_m, 5e-4, s.stock_m);
        if (s.tool_mesh_path.empty()) fail("tool.mesh", "a mesh tool needs its mesh file", "none");
    } else {
        range("tool.radius_m", s.tool.radius_m, 5e-4, 0.25 * s.stock_m);
    }
    if (s.tool.kind == ToolKind::kFlatEnd) range("tool.length_m", s.tool.length_m, 5e-4, s.stock_m);
    if (s.points < 1 || s.points > 64) fail("points", "must be between 1 and 64", std::to_string(s.points));
    try {
        (void)devices::profile_by_name(s.device);
    } catch (const Error&) {
        fail("device", "must be omni, wand, 6dof, falcon or tracked", "'" + s.device + "'");
    }
    range("workspace_scale", s.workspace_scale, kWorkspaceScaleMin, kWorkspaceScaleMax);
    range("stiffness_n_per_m", s.stiffness_n_per_m, 0.0, 1e5, true);
    range("damping_n_s_per_m", s.damping_n_s_per_m, 0.0, 1e3);
    range("static_friction", s.static_friction, 0.0, 10.0);
    range("dynamic_friction", s.dynamic_friction, 0.0, s.static_friction);
    range("period_s", s.period_s, 1e-4, 1e-2);
    if (s.history_budget_bytes < (std::size_t{1} << 20) || s.history_budget_bytes > (std::size_t{1} << 40))
        fail("history_budget_bytes", "must be between 1 MiB and 1 TiB", std::to_string(s.history_budget_bytes));
    if (s.clay_group_sweeps < 1 || s.clay_group_sweeps > compute::kClayGroupSweepsMax)
        fail("clay_group_sweeps", "must be 1.." + std::to_string(compute::kClayGroupSweepsMax),
             std::to_string(s.clay_group_sweeps));
    try {
        (void)parse_tool_op(s.op);
        (void)haptics::parse_workspace_mode(s.workspace_mode);
        const haptics::HapticLoopConfig cfg = loop_config(s, 0);  // points for the tool (its mesh), materials, material id
        if (s.tool.kind == ToolKind::kMesh && std::abs(cfg.tool.radius_m - s.tool.radius_m) > 1e-9 * s.tool.radius_m)
            throw Error("tool.radius_m: " + format_number(s.tool.radius_m) + " m is not the tool mesh's bounding radius " +
                        format_number(cfg.tool.radius_m) + " m");
    } catch (const Error& e) {
        throw Error(source + ": settings: " + e.what());
    }
    validate_more_workpieces(s, source);
}

std::pair<std::uint32_t, std::uint64_t> file_crc32(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw Error(path + ": cannot read");
    std::uint32_t crc = 0;
    std::uint64_t bytes = 0;
    char buf[1 << 16];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) {
        crc = crc32_ieee(buf, n, crc);
        bytes += n;
    }
    const bool bad = std::ferror(f) != 0;
    std::fclose(f);
    if (bad) throw Error(path + ": cannot read");
    return {crc, bytes};
}

compute::JournalApplyFrom replay_settings(const SessionSpec& s) {
    compute::JournalApplyFrom from;
    from.history_budget_bytes = s.history_budget_bytes;
    from.remove_islands = !s.keep_islands;
    from.clay_group_sweeps = s.clay_group_sweeps;
    return from;
}

std::string settings_at_resolution(const std::string& settings_json, int resolution) {
    nlohmann::json j = nlohmann::json::parse(settings_json, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("resolution")) return settings_json;
    j["resolution"] = resolution;
    return j.dump();
}

std::string spec_to_json(const SessionSpec& s) {
    json materials = json::array();
    for (const MaterialEntry& m : s.materials)
        materials.push_back({{"id", m.id},
                             {"stiffness_n_per_m", m.material.stiffness_n_per_m},
                             {"damping_n_s_per_m", m.material.damping_n_s_per_m},
                             {"static_friction", m.material.static_friction},
                             {"dynamic_friction", m.material.dynamic_friction}});
    json tool{{"shape", to_string(s.tool.kind)}, {"radius_m", s.tool.radius_m}, {"length_m", s.tool.length_m}};
    if (s.tool.kind == ToolKind::kMesh) {
        tool["mesh"] = s.tool_mesh_path;
        tool["size_m"] = s.tool_size_m;
        tool["mesh_crc32"] = s.tool_mesh_crc32;
        tool["mesh_bytes"] = s.tool_mesh_bytes;
    }
    json elastic = json::array();
    for (const haptics::ElasticSphere& e : s.elastic_objects)
        elastic.push_back({{"centre_m", vec(e.centre_m)},
                           {"radius_m", e.radius_m},
                           {"stiffness_n_per_m", e.stiffness_n_per_m},
                           {"influence_radius_m", e.influence_m}});
    json j{{"mesh_path", s.mesh_path},
           {"mesh_crc32", s.mesh_crc32},
           {"mesh_bytes", s.mesh_bytes},
           {"model_path", s.model_path},
           {"model_crc32", s.model_crc32},
           {"model_bytes", s.model_bytes},
           {"study_model", s.study_model},
           {"resolution", s.resolution},
           {"stock_m", s.stock_m},
           {"workpiece_centre_m", vec(s.workpiece_centre_m)},
           {"tool", tool},
           {"points", s.points},
           {"device_driver", s.device_driver},
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
           {"symmetry", s.symmetry},
           {"materials", materials},
           {"period_s", s.period_s},
           {"history_budget_bytes", s.history_budget_bytes},
           {"keep_islands", s.keep_islands},
           {"clay_group_sweeps", s.clay_group_sweeps}};
    if (!elastic.empty()) j["elastic_objects"] = elastic;  // absent in sessions without them, as before
    if (!workpiece_pose(s).is_identity()) {                  // absent for an unposed workpiece, as before
        const Quat& q = s.workpiece_turn;
        j["workpiece_turn"] = json::array({q.w, q.x, q.y, q.z});
        j["workpiece_shift_m"] = vec(s.workpiece_shift_m);
    }
    if (!s.references.empty()) {                            // absent in sessions without them, as before
        json refs = json::array();
        for (const ReferenceSpec& r : s.references) refs.push_back(reference_settings_json(r));
        j["references"] = refs;
    }
    if (!s.more_workpieces.empty()) j["more_workpieces"] = more_workpieces_json(s);  // absent with one, as before
    if (s.palette != default_material_palette()) {         // absent with the default palette, as before
        json palette = json::array();
        for (int i = 0; i < kPaletteSize; ++i) {
            const PaletteEntry& e = s.palette.entries[i];
            palette.push_back({{"id", i}, {"name", e.name}, {"rgb", e.rgb}});
        }
        j["palette"] = palette;
    }
    return j.dump();
}

SessionSpec spec_from_json(const std::string& text, const std::string& source) {
    json j;
    try {
        j = json::parse(text);
    } catch (const json::exception& e) {
        throw Error(source + ": settings are not JSON: " + e.what());
    }
    if (!j.is_object()) throw Error(source + ": settings must be a JSON object");
    auto field = [&](const json& o, const std::string& name) -> const json& {
        if (!o.is_object() || !o.contains(name)) throw Error(source + ": settings field '" + name + "' is missing");
        return o.at(name);
    };
    auto get = [&](const json& o, const std::string& name, auto& out) {
        try {
            field(o, name).get_to(out);
        } catch (const json::exception&) {
            throw Error(source + ": settings field '" + name + "' has the wrong type");
        }
    };
    auto get_vec_of = [&](const json& o, const char* name, Vec3& out) {
        const auto& a = field(o, name);
        if (!a.is_array() || a.size() != 3 || !a[0].is_number() || !a[1].is_number() || !a[2].is_number())
            throw Error(source + ": settings field '" + name + "' must be [x, y, z]");
        out = Vec3(a[0].get<double>(), a[1].get<double>(), a[2].get<double>());
    };
    auto get_vec = [&](const char* name, Vec3& out) { get_vec_of(j, name, out); };
    SessionSpec s;
    get(j, "mesh_path", s.mesh_path);
    get(j, "resolution", s.resolution);
    get(j, "stock_m", s.stock_m);
    get_vec("workpiece_centre_m", s.workpiece_centre_m);
    if (j.contains("workpiece_turn")) {  // added later: sessions before had an unposed workpiece
        const json& q = j.at("workpiece_turn");
        if (!q.is_array() || q.size() != 4 || !q[0].is_number() || !q[1].is_number() || !q[2].is_number() ||
            !q[3].is_number())
            throw Error(source + ": settings field 'workpiece_turn' must be [w, x, y, z]");
        s.workpiece_turn = Quat(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(), q[3].get<double>());
        get_vec("workpiece_shift_m", s.workpiece_shift_m);
    }
    if (j.contains("tool")) {
        const json& t = j.at("tool");
        std::string shape;
        get(t, "shape", shape);
        s.tool.kind = parse_tool_kind(shape, source + ": settings field 'tool.shape'");
        get(t, "radius_m", s.tool.radius_m);
        get(t, "length_m", s.tool.length_m);
        if (s.tool.kind == ToolKind::kMesh) {
            get(t, "mesh", s.tool_mesh_path);
            get(t, "size_m", s.tool_size_m);
            get(t, "mesh_crc32", s.tool_mesh_crc32);
            get(t, "mesh_bytes", s.tool_mesh_bytes);
        }
    } else {  // recordings made before tool shapes: a ball
        s.tool = ToolShape{ToolKind::kBall, 0.0, 0.0, 0};
        get(j, "tool_radius_m", s.tool.radius_m);
    }
    get(j, "points", s.points);
    get(j, "device", s.device);
    get(j, "workspace_mode", s.workspace_mode);
    get(j, "workspace_scale", s.workspace_scale);
    get_vec("device_origin_m", s.device_origin_m);
    get(j, "stiffness_n_per_m", s.stiffness_n_per_m);
    get(j, "damping_n_s_per_m", s.damping_n_s_per_m);
    get(j, "static_friction", s.static_friction);
    get(j, "dynamic_friction", s.dynamic_friction);
    get(j, "cutting", s.cutting);
    get(j, "period_s", s.period_s);
    // Added later: recordings made before them sculpted with subtract, one material, the simulated driver.
    if (j.contains("op")) get(j, "op", s.op);
    if (j.contains("material")) get(j, "material", s.material);
    if (j.contains("symmetry")) get(j, "symmetry", s.symmetry);  // added later: sessions before had none
    if (j.contains("device_driver")) get(j, "device_driver", s.device_driver);
    if (j.contains("history_budget_bytes")) get(j, "history_budget_bytes", s.history_budget_bytes);
    // Sessions before speck removal kept every piece: their recordings and journals replay that way.
    s.keep_islands = true;
    if (j.contains("keep_islands")) get(j, "keep_islands", s.keep_islands);
    // Sessions before the group size was recorded grouped clay sweeps 16 at a time.
    s.clay_group_sweeps = 16;
    if (j.contains("clay_group_sweeps")) get(j, "clay_group_sweeps", s.clay_group_sweeps);
    if (j.contains("mesh_crc32")) get(j, "mesh_crc32", s.mesh_crc32);
    if (j.contains("mesh_bytes")) get(j, "mesh_bytes", s.mesh_bytes);
    if (j.contains("model_path")) get(j, "model_path", s.model_path);
    if (j.contains("model_crc32")) get(j, "model_crc32", s.model_crc32);
    if (j.contains("model_bytes")) get(j, "model_bytes", s.model_bytes);
    if (j.contains("study_model")) get(j, "study_model", s.study_model);
    if (j.contains("materials")) {
        const json& ms = j.at("materials");
        if (!ms.is_array()) throw Error(source + ": settings field 'materials' must be an array");
        for (const json& m : ms) {
            MaterialEntry e;
            get(m, "id", e.id);
            get(m, "stiffness_n_per_m", e.material.stiffness_n_per_m);
            get(m, "damping_n_s_per_m", e.material.damping_n_s_per_m);
            get(m, "static_friction", e.material.static_friction);
            get(m, "dynamic_friction", e.material.dynamic_friction);
            s.materials.push_back(e);
        }
    }
    if (j.contains("palette")) {
        const json& ps = j.at("palette");
        if (!ps.is_array() || ps.size() != static_cast<std::size_t>(kPaletteSize))
            throw Error(source + ": settings field 'palette' must be an array of " + std::to_string(kPaletteSize) + " entries");
        for (int i = 0; i < kPaletteSize; ++i) {
            int id = -1;
            get(ps[i], "id", id);
            if (id != i) throw Error(source + ": settings field 'palette' must list ids 0.." + std::to_string(kPaletteSize - 1) + " in order");
            get(ps[i], "name", s.palette.entries[i].name);
            get(ps[i], "rgb", s.palette.entries[i].rgb);
        }
        if (const std::string why = palette_problem(s.palette); !why.empty())
            throw Error(source + ": settings field 'palette': " + why);
    }
    if (j.contains("elastic_objects")) {
        const json& es = j.at("elastic_objects");
        if (!es.is_array()) throw Error(source + ": settings field 'elastic_objects' must be an array");
        for (std::size_t i = 0; i < es.size(); ++i) {
            haptics::ElasticSphere e;
            get_vec_of(es[i], "centre_m", e.centre_m);
            get(es[i], "radius_m", e.radius_m);
            get(es[i], "stiffness_n_per_m", e.stiffness_n_per_m);
            get(es[i], "influence_radius_m", e.influence_m);
            haptics::validate(e, source + ": settings field 'elastic_objects[" + std::to_string(i) + "]'");
            s.elastic_objects.push_back(e);
        }
    }
    if (j.contains("more_workpieces")) read_more_workpieces(j.at("more_workpieces"), s, source);
    if (j.contains("references")) {
        const json& rs = j.at("references");
        if (!rs.is_array() || rs.size() > kMaxSceneReferences)
            throw Error(source + ": settings field 'references' must be an array of at most " +
                        std::to_string(kMaxSceneReferences) + " objects");
        for (std::size_t i = 0; i < rs.size(); ++i)
            s.references.push_back(
                reference_from_settings_json(rs[i], source + ": settings field 'references[" + std::to_string(i) + "]'"));
    }
    return s;
}

}  // namespace tridex::app
