// app/scene/run_scene.cpp - reading and checking the scene of `tridex run`.
#include "app/scene/run_scene.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>

#include <nlohmann/json.hpp>

#include "app/support/assets.hpp"
#include "app/support/json_fields.hpp"
#include "app/support/json_file.hpp"
#include "app/scene/scene_materials.hpp"
#include "app/scene/scene_workpieces.hpp"
#include "app/scene/workpiece_list.hpp"
#include "app/scene/trial_table.hpp"
#include "compute/model/tdx_file.hpp"
#include "devices/net/enet_link.hpp"
#include "devices/net/link_wire.hpp"
#include "devices/tracking/dtrack_receiver.hpp"
#include "core/error.hpp"
#include "core/symmetry.hpp"
#include "core/format.hpp"
#include "devices/registry/device_registry.hpp"
#include "app/scene/tool_mesh.hpp"
#include "haptics/tool_points.hpp"

namespace tridex::app {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string fmt(double v) { return format_number(v); }

Quat quat_of(const Fields& f, const json& v, const std::string& field) {
    if (!v.is_array() || v.size() != 4) f.fail(field, "must be an array of 4 numbers [w, x, y, z]");
    double q[4];
    for (int k = 0; k < 4; ++k) {
        if (!v[k].is_number()) f.fail(field, "must be an array of 4 numbers [w, x, y, z]");
        q[k] = v[k].get<double>();
    }
    const Quat out(q[0], q[1], q[2], q[3]);
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!std::isfinite(n) || std::abs(n - 1.0) > 1e-6) f.fail(field, "must be a unit quaternion (|q| = 1 within 1e-6)");
    return out;
}

void read_tool(Fields& top, RunScene& s, const std::string& base_dir) {
    SessionSpec& sp = s.spec;
    const json* t = top.get("tool");
    if (t) {
        Fields f(*t, top.source(), "tool");
        const std::string shape = f.text("shape", to_string(sp.tool.kind));
        sp.tool.kind = parse_tool_kind(shape, top.source() + ": field 'tool.shape'");
        if (sp.tool.kind == ToolKind::kMesh) {
            // A closed mesh, its tip on the HIP and +y its axis (app/scene/tool_mesh.hpp), longest side size_m.
            const std::string mesh = f.text("mesh", "");
            if (mesh.empty()) f.fail("tool.mesh", "a mesh tool needs its closed mesh file");
            const double size_m = f.number("size_m", 0.012, 0.001, 0.25 * sp.stock_m);
            const fs::path p = fs::path(mesh).is_absolute() ? fs::path(mesh) : fs::path(base_dir) / mesh;
            if (!fs::is_regular_file(p)) f.fail("tool.mesh", "no such file: " + p.string());
            for (const char* other : {"radius_m", "length_m"})
                if (f.get(other)) f.fail(std::string("tool.") + other, "a mesh tool's size is size_m");
            set_tool_mesh(sp, p.string(), size_m, top.source() + ": field 'tool.mesh'");
        } else {
            sp.tool.radius_m = f.number("radius_m", sp.tool.radius_m, 0.0005, 0.25 * sp.stock_m);
        }
        if (sp.tool.kind == ToolKind::kFlatEnd)
            sp.tool.length_m = f.number("length_m", 4.0 * sp.tool.radius_m, 0.0005, sp.stock_m);
        else if (sp.tool.kind == ToolKind::kBall && f.get("length_m"))
            f.fail("tool.length_m", "only a flat_end tool has a length");
        sp.stiffness_n_per_m = f.number("stiffness_n_per_m", sp.stiffness_n_per_m, 0.0, 1e5, true);
        sp.damping_n_s_per_m = f.number("damping_n_s_per_m", sp.damping_n_s_per_m, 0.0, 1e3);
        f.finish();
    } else if (sp.tool.radius_m > 0.25 * sp.stock_m) {
        top.fail("tool.radius_m", "the default " + fmt(sp.tool.radius_m) + " m exceeds a quarter of workpiece.stock_m");
    }
}

// The scene's "device" block: the driver and what its capabilities say it reads (profile, firmware, address,
// tracked target, the key of a sealed link, its own numeric options). Fields a driver does not read are refused as
// unknown.
void read_device(Fields& top, RunScene& s, const std::string& base_dir) {
    const json* d = top.get("device");
    if (!d) return;
    s.device_named = true;
    Fields f(*d, top.source(), "device");
    const devices::DeviceRegistry& registry = devices::builtin_registry();
    s.spec.device_driver = f.text("driver", s.spec.device_driver);
    // Drivers a scene can name: every available one of the registry but the recorded input (a recording's).
    std::string usable;
    for (const devices::DriverInfo& i : registry.drivers())
        if (i.available && i.caps.input != devices::InputKind::kRecorded) usable += (usable.empty() ? "" : ", ") + i.name;
    const devices::DriverInfo* driver = registry.find(s.spec.device_driver);
    if (!driver)
        f.fail("device.driver", "'" + s.spec.device_driver + "' is not a driver; use " + usable);
    else if (driver->caps.input == devices::InputKind::kRecorded)
        f.fail("device.driver", "'" + driver->name + "' plays a recording: use `tridex replay FILE`; a scene can use " + usable);
    else if (!driver->available)
        f.fail("device.driver", "'" + driver->name + "' is known hardware without a driver in this build yet; use " + usable);
    const devices::DriverCapabilities& caps = driver->caps;
    // Hardware: refuse at once, with one line, when none is plugged in (libusb enumeration).
    if (!driver->usb_ids.empty()) {
        bool plugged = false;
        for (const devices::DetectedDevice& u : registry.detect()) plugged = plugged || u.driver == driver->name;
        if (!plugged)
            f.fail("device.driver", "'" + driver->name + "': no " + driver->product + " is plugged in (USB " +
                                        devices::usb_id_string(driver->usb_ids.front()) +
                                        "; `tridex devices` lists what is)" +
                                        (driver->stand_in.empty() ? std::string()
                                                                  : "; " + driver->stand_in + " runs the same driver without one"));
    }
    s.spec.device = f.text("profile", s.spec.device);
    // A driver of one product drives its own profile, whatever the scene says (the Falcon's; a tracked tool's).
    if (!caps.fixed_profile.empty()) s.spec.device = caps.fixed_profile;
    if (caps.input == devices::InputKind::kTracked) {
        s.tracked_port = f.integer("port", s.tracked_port, 1, 65535);
        s.tracked_id = f.integer("id", s.tracked_id, 0, caps.target_ids - 1);
        s.tracked_bind = f.text("bind_address", s.tracked_bind);
        s.tracked_timeout_s = f.number("timeout_s", s.tracked_timeout_s, 0.0, 10.0, true);
    }
    if (caps.takes_firmware) s.spec.device_firmware = f.text("firmware", s.spec.device_firmware);
    if (caps.input == devices::InputKind::kRemote) {  // a device served by `tridex device-server`
        s.spec.device_serial = f.text("address", s.spec.device_serial);
        try {
            std::string host;
            std::uint16_t port = 0;
            devices::net::split_host_port(s.spec.device_serial, "address", host, port);
        } catch (const Error& e) {
            f.fail("device.address", std::string(e.what()) + " (the device server's --listen)");
        }
        s.spec.haptic_rendering = f.text("haptic_rendering", s.spec.haptic_rendering);
        try {
            (void)devices::net::rendering_mode_from(s.spec.haptic_rendering);
        } catch (const Error&) {
            f.fail("device.haptic_rendering", "'" + s.spec.haptic_rendering + "' is not distributed or local");
        }
    }
    if (caps.seals_link) {  // the key of a sealed link: a file (relative to the scene) or a variable's name
        const std::string key_file = f.text("key_file", "");
        if (!key_file.empty())
            s.spec.device_key_file = fs::path(key_file).is_absolute() ? key_file : (fs::path(base_dir) / key_file).string();
        s.spec.device_passphrase_env = f.text("passphrase_env", s.spec.device_passphrase_env);
        if (!s.spec.device_key_file.empty() && !s.spec.device_passphrase_env.empty())
            f.fail("device.key_file", "device.passphrase_env is set too: choose one");
    }
    for (const devices::DriverOption& o : caps.options)  // other drivers refuse these fields as unknown
        if (f.get(o.name)) s.device_options[o.name] = f.number(o.name, o.fallback, o.min, o.max, o.min_exclusive);
    try {
        (void)device_profile(s.spec.device);
    } catch (const Error&) {
        f.fail("device.profile", "'" + s.spec.device + "' is not one of omni, wand, 6dof, falcon, tracked");
    }
    f.finish();
}

void read_op(Fields& top, RunScene& s) {
    s.spec.op = top.text("op", s.spec.op);
    try {
        (void)parse_tool_op(s.spec.op);
    } catch (const Error&) {
        top.fail("op", "'" + s.spec.op + "' is not one of subtract, union, paint, push, smooth, pull, none");
    }
    s.spec.symmetry = top.text("symmetry", s.spec.symmetry);
    try {
        s.spec.symmetry = to_string(parse_symmetry(s.spec.symmetry, "symmetry"));
    } catch (const Error&) {
        top.fail("symmetry", "'" + s.spec.symmetry + "' is not one of " + symmetry_forms());
    }
    s.spec.clay_group_sweeps =
        static_cast<std::size_t>(top.integer("clay_group_sweeps", static_cast<int>(s.spec.clay_group_sweeps), 1,
                                             static_cast<int>(compute::kClayGroupSweepsMax)));
}

void read_haptics(Fields& top, RunScene& s) {
    SessionSpec& sp = s.spec;
    const json* h = top.get("haptics");
    if (h) {
        Fields f(*h, top.source(), "haptics");
        sp.points = f.integer("points", sp.points, 1, haptics::kMaxToolPoints);
        sp.static_friction = f.number("static_friction", sp.static_friction, 0.0, 10.0);
        sp.dynamic_friction = f.number("dynamic_friction", sp.dynamic_friction, 0.0, 10.0);
        if (sp.dynamic_friction > sp.static_friction)
            f.fail("haptics.dynamic_friction", "must not exceed static_friction (" + fmt(sp.static_friction) + ")");
        sp.cutting = f.boolean("cutting_force", sp.cutting);
        f.finish();
    }
    try {  // the points must exist on the tool
        const TriMesh tool_mesh = sp.tool.kind == ToolKind::kMesh ? load_tool_mesh(sp.tool_mesh_path, sp.tool_size_m) : TriMesh{};
        (void)haptics::tool_points_for(sp.tool, sp.points, "tool", &tool_mesh);
    } catch (const Error& e) {
        top.fail("haptics.points", e.what());
    }
}

void read_workspace(Fields& top, RunScene& s) {
    const json* w = top.get("workspace");
    if (!w) return;
    Fields f(*w, top.source(), "workspace");
    const std::string mode = f.text("mode", s.spec.workspace_mode);
    try {
        (void)haptics::parse_workspace_mode(mode);
    } catch (const Error& e) {
        f.fail("workspace.mode", e.what());
    }
    s.spec.workspace_mode = mode;
    if (const json* scale = f.get("scale"); scale && scale->is_string()) {
        if (scale->get<std::string>() != "fit")
            f.fail("workspace.scale", "must be a number (device -> world gain) or \"fit\"");
        s.workspace_fit = true;
    } else {
        s.spec.workspace_scale = f.number("scale", s.spec.workspace_scale, kWorkspaceScaleMin, kWorkspaceScaleMax);
    }
    f.finish();
}

void read_keys(Fields& top, RunScene& s) {
    const json* keys = top.get("keys");
    if (!keys) return;
    if (!keys->is_array()) top.fail("keys", "must be a list of {\"t_s\": seconds, \"press\": \"ctrl+z\"}");
    double prev = 0.0;
    for (std::size_t i = 0; i < keys->size(); ++i) {
        const std::string name = "keys[" + std::to_string(i) + "]";
        Fields f((*keys)[i], top.source(), name);
        ScriptedKey k;
        k.t_s = f.number("t_s", -1.0, 0.0, 86400.0);
        if (k.t_s < 0.0) f.fail(name + ".t_s", "is missing");
        if (k.t_s < prev) f.fail(name + ".t_s", "must not be earlier than the key before it");
        prev = k.t_s;
        k.text = f.text("press", "");
        if (k.text.empty()) f.fail(name + ".press", "is missing (e.g. \"ctrl+z\")");
        k.chord = parse_key_chord(k.text, top.source() + ": field '" + name + ".press'");
        f.finish();
        s.keys.push_back(k);
    }
}

void read_cursor(Fields& top, RunScene& s) {
    const json* cur = top.get("cursor");
    if (!cur) return;
    if (!cur->is_array()) top.fail("cursor", "must be a list of {\"t_s\", \"x_px\", \"y_px\", \"buttons\"}");
    double prev = 0.0;
    for (std::size_t i = 0; i < cur->size(); ++i) {
        const std::string name = "cursor[" + std::to_string(i) + "]";
        Fields f((*cur)[i], top.source(), name);
        CursorPoint p;
        p.t_s = f.number("t_s", -1.0, 0.0, 86400.0);
        if (p.t_s < 0.0) f.fail(name + ".t_s", "is missing");
        if (p.t_s < prev) f.fail(name + ".t_s", "must not be earlier than the point before it");
        prev = p.t_s;
        p.x_px = f.number("x_px", 0.0, -1e5, 1e5);
        p.y_px = f.number("y_px", 0.0, -1e5, 1e5);
        p.buttons = static_cast<std::uint32_t>(f.integer("buttons", 0, 0, 3));
        p.wheel = f.number("wheel", 0.0, -1000.0, 1000.0);
        f.finish();
        s.cursor.points.push_back(p);
    }
    const devices::DriverInfo* driver = devices::builtin_registry().find(s.spec.device_driver);
    if (!s.cursor.empty() && !(driver && driver->caps.app_sets_hand))
        top.fail("cursor", "a scripted cursor drives the mouse stylus: set \"device\": {\"driver\": \"mouse\"}");
}

void read_stroke(Fields& top, RunScene& s) {
    const json* st = top.get("stroke");
    if (st && st->is_string()) {
        if (st->get<std::string>() != "none") top.fail("stroke", "must be an object or \"none\"");
        s.has_stroke = false;
        return;
    }
    s.has_stroke = true;
    StrokeParams& p = s.stroke;
    p.duration_s = 3.0;
    p.length_m = 0.08;
    p.depth_m = 0.004;
    p.clearance_m = 0.02;
    if (st) {
        Fields f(*st, top.source(), "stroke");
        p.duration_s = f.number("duration_s", p.duration_s, 0.1, 600.0);
        p.length_m = f.number("length_m", p.length_m, 0.0, 10.0, true);
        p.depth_m = f.number("depth_m", p.depth_m, 0.0, 1.0);
        p.clearance_m = f.number("clearance_m", p.clearance_m, 0.0, 1.0);
        p.start_s = f.number("start_s", p.start_s, 0.0, 600.0);
        const std::string axis = f.text("press_axis", "z");
        if (axis != "y" && axis != "z") f.fail("stroke.press_axis", "must be \"z\" (from the viewer) or \"y\" (from above)");
        p.press_axis = axis == "y" ? 1 : 2;
        p.passes = f.integer("passes", 1, 1, 16);
        s.stroke_workpiece = static_cast<std::size_t>(f.integer("workpiece", 0, 0, static_cast<int>(workpiece_count(s.spec)) - 1));
        if (const json* mv = f.get("moves")) {
            if (!mv->is_array()) f.fail("stroke.moves", "must be a list of \"jump\" and \"drag\"");
            if (static_cast<int>(mv->size()) > p.passes - 1)
                f.fail("stroke.moves", "has " + std::to_string(mv->size()) + " entries; " + std::to_string(p.passes) +
                                           " passes have " + std::to_string(p.passes - 1) + " moves between them");
            for (std::size_t i = 0; i < mv->size(); ++i) {
                const json& m = (*mv)[i];
                if (!m.is_string() || (m.get<std::string>() != "jump" && m.get<std::string>() != "drag"))
                    f.fail("stroke.moves[" + std::to_string(i) + "]", "must be \"jump\" or \"drag\"");
                p.moves.push_back(m.get<std::string>() == "jump" ? WorkspaceMove::kJump : WorkspaceMove::kDrag);
            }
        }
        f.finish();
    }
    // The planner keeps the tool's lowest point along the press direction depth_m below the surface: a ball's
    // lies a radius from its centre; a flat end pressed from above (its axis +y) is its own lowest point.
    // A mesh tool reaches as far below its tip as its mesh does along -press_axis (0 from above: its tip).
    p.tool_radius_m = s.spec.tool.kind == ToolKind::kMesh
                          ? tool_mesh_reach_m(load_tool_mesh(s.spec.tool_mesh_path, s.spec.tool_size_m), p.press_axis)
                      : s.spec.tool.kind == ToolKind::kFlatEnd && p.press_axis == 1 ? 0.0
                                                                                     : s.spec.tool.radius_m;
}

void read_display(Fields& top, RunScene& s) {
    const json* d = top.get("display");
    if (!d) return;
    const std::string src = top.source() + ": field 'display'";
    if (d->is_string()) {
        const std::string name = d->get<std::string>();
        if (name == "desktop")
            s.display = renderer::DisplayConfig::desktop();
        else if (name == "powerwall")
            s.display = renderer::DisplayConfig::powerwall();
        else
            top.fail("display", "preset '" + name + "' is not one of desktop, powerwall (or give a display config object)");
        return;
    }
    s.display = renderer::display_config_from_json(*d, src);
}

void read_head(Fields& top, RunScene& s) {
    s.head_pose = Pose{s.display.default_head_m, Quat(1.0, 0.0, 0.0, 0.0)};
    const json* h = top.get("head");
    if (!h) return;
    Fields f(*h, top.source(), "head");
    s.head = parse_head_mode(f.text("provider", "fixed"), top.source() + ": field 'head.provider'");
    s.head_pose.position = f.vec3("position_m", s.head_pose.position);
    if (s.head == HeadMode::kFixed && f.get("position_m")) {
        // The fixed head must see the screen from in front (the off-axis frustum needs the eye before its plane).
        const renderer::Screen& sc = s.display.screen;
        const Vec3 n = glm::cross(sc.lower_right - sc.lower_left, sc.upper_left - sc.lower_left);
        const double d = glm::length(n) > 0.0 ? glm::dot(s.head_pose.position - sc.lower_left, glm::normalize(n)) : 1.0;
        if (!(d > 0.0))
            f.fail("head.position_m", "must be in front of the display's screen, got " + fmt(d) +
                                          " m along the screen's normal");
    }
    if (const json* o = f.get("orientation_wxyz")) s.head_pose.orientation = quat_of(f, *o, "head.orientation_wxyz");
    s.head_loop = f.boolean("loop", false);
    s.tracker_timeout_s = f.number("tracker_timeout_s", s.tracker_timeout_s, 0.0, 10.0, true);
    s.dtrack_port = f.integer("port", s.dtrack_port, 1, 65535);
    s.dtrack_body = f.integer("body", s.dtrack_body, 0, devices::kDTrackKeptBodies - 1);
    s.dtrack_bind = f.text("bind_address", s.dtrack_bind);
    if (const json* w = f.get("waypoints")) {
        if (!w->is_array()) f.fail("head.waypoints", "must be an array of {t_s, position_m, orientation_wxyz}");
        for (std::size_t i = 0; i < w->size(); ++i) {
            Fields wf((*w)[i], top.source(), "head.waypoints[" + std::to_string(i) + "]");
            renderer::HeadWaypoint wp;
            wp.t_s = wf.number("t_s", 0.0, 0.0, 1e6);
            const json* p = wf.get("position_m");
            if (!p) wf.fail(wf.path("position_m"), "missing");
            wp.pose.position = wf.vec3_of(*p, wf.path("position_m"));
            if (const json* o = wf.get("orientation_wxyz")) wp.pose.orientation = quat_of(wf, *o, wf.path("orientation_wxyz"));
            wf.finish();
            if (i > 0 && !(wp.t_s > s.head_waypoints.back().t_s))
                wf.fail(wf.path("t_s"), "times must strictly increase");
            s.head_waypoints.push_back(wp);
        }
    }
    if (s.head == HeadMode::kScripted && s.head_waypoints.empty())
        f.fail("head.waypoints", "the scripted head needs at least one waypoint");
    if (s.head_loop && s.head_waypoints.size() < 2) f.fail("head.loop", "a looping script needs two waypoints or more");
    f.finish();
}

void read_wand(Fields& top, RunScene& s) {
    const json* w = top.get("wand");
    if (!w) return;
    Fields f(*w, top.source(), "wand");
    const std::string provider = f.text("provider", "none");
    if (provider != "none" && provider != "dtrack") f.fail("wand.provider", "'" + provider + "' is not one of none, dtrack");
    s.wand_dtrack = provider == "dtrack";
    s.wand_port = f.integer("port", s.wand_port, 1, 65535);
    s.wand_flystick = f.integer("flystick", s.wand_flystick, 0, devices::kDTrackKeptFlysticks - 1);
    s.wand_bind = f.text("bind_address", s.wand_bind);
    s.wand_timeout_s = f.number("timeout_s", s.wand_timeout_s, 0.0, 10.0, true);
    f.finish();
}

// A study scene: the wand as the tool, nothing carved; the workpiece, tool, op, haptics and stroke come from it.
void read_study(Fields& top, const json& j, RunScene& s, const std::string& base_dir) {
    const json* st = top.get("study");
    if (!st) return;
    for (const char* name : {"workpiece", "tool", "op", "material", "haptics", "stroke", "cursor", "objects", "references"})
        if (j.contains(name))
            top.fail(name, "a study scene decides it (the wand, its felt walls, no carving); remove it or the \"study\" field");
    Fields f(*st, top.source(), "study");
    RunStudy& r = s.study;
    r.enabled = true;
    const json* file = f.get("scene");
    if (!file || !file->is_string()) f.fail("study.scene", "must name a study scene file (JSON)");
    fs::path p(file->get<std::string>());
    if (p.is_relative()) p = fs::path(base_dir) / p;
    if (!fs::is_regular_file(p)) f.fail("study.scene", "no such file: " + p.string());
    r.scene = study::read_study_scene(p.string());
    r.model = f.text("model", r.model);
    if (r.model != "haptic_training" && r.model != "visual_training" && r.model != "test")
        f.fail("study.model", "'" + r.model + "' is not one of haptic_training, visual_training, test");
    r.seed = static_cast<std::uint32_t>(f.integer("seed", 1, 1, 2147483647));
    r.trial = f.integer("trial", 1, 1, 1000);
    r.end_at_end_cap = f.boolean("end_at_end_cap", false);
    r.phase_line = f.text("phase_line", "");
    r.participant = f.text("participant", "");
    r.group = f.text("group", "");
    if (!r.participant.empty() && !study::valid_participant_id(r.participant))
        f.fail("study.participant", "an ID of 1..64 letters, digits, '_' or '-' (no names)");
    if (!r.group.empty() && r.group != "haptic" && r.group != "visual") f.fail("study.group", "use haptic or visual");
    if (r.participant.empty() != r.group.empty()) f.fail("study.group", "give participant and group together");
    f.finish();
    SessionSpec& sp = s.spec;
    sp.tool = ToolShape{ToolKind::kFlatEnd, r.scene.wand_radius_m, r.scene.wand_length_m, 0};
    sp.points = 2;
    sp.op = "none";
    sp.cutting = false;
    sp.mesh_path = r.scene.path;
    sp.study_model = r.model;
    s.has_stroke = false;
}

void read_objects(Fields& top, RunScene& s) {
    const json* o = top.get("objects");
    if (!o) return;
    s.objects = scene_spheres_from_json(*o, top.source());
    for (const SceneSphere& x : s.objects) s.spec.elastic_objects.push_back(x.sphere);
}

void read_references(Fields& top, RunScene& s, const std::string& base_dir) {
    const json* r = top.get("references");
    if (!r) return;
    s.spec.references = references_from_scene_json(*r, top.source(), base_dir);
}

}  // namespace

const char* to_string(HeadMode mode) {
    switch (mode) {
        case HeadMode::kFixed: return "fixed";
        case HeadMode::kScripted: return "scripted";
        case HeadMode::kTracker: return "tracker";
        case HeadMode::kDTrack: return "dtrack";
    }
    return "fixed";
}

HeadMode parse_head_mode(const std::string& name, const std::string& what) {
    for (HeadMode m : {HeadMode::kFixed, HeadMode::kScripted, HeadMode::kTracker, HeadMode::kDTrack})
        if (name == to_string(m)) return m;
    throw Error(what + ": head provider '" + name + "' is not one of fixed, scripted, tracker, dtrack");
}

SessionSpec RunScene::default_spec() {
    SessionSpec s;
    s.resolution = 128;
    s.stock_m = 0.12;
    s.workpiece_centre_m = Vec3(0.0, 0.0, 0.05);
    s.tool = ToolShape{ToolKind::kBall, 0.006, 0.0, 0};
    s.static_friction = 0.0;  // a scene's contact has no friction and no cutting force unless it asks
    s.dynamic_friction = 0.0;
    s.cutting = false;
    return s;
}

RunScene run_scene_from_json(const json& j, const std::string& source, const std::string& base_dir) {
    RunScene s;
    s.source = source;
    Fields top(j, source, "");
    const json* named = top.get("material");
    read_scene_workpieces(top, s.spec, base_dir, top.get("materials") || (named && named->is_string()));
    read_tool(top, s, base_dir);
    read_device(top, s, base_dir);
    read_op(top, s);
    read_scene_materials(top, s.spec);
    read_haptics(top, s);
    read_workspace(top, s);
    read_stroke(top, s);
    read_keys(top, s);
    read_cursor(top, s);
    read_display(top, s);
    read_head(top, s);
    read_wand(top, s);
    if (const json* b = top.get("bindings")) {
        if (!b->is_object()) top.fail("bindings", "must be an object {\"tool\": {...}, \"wand\": {...}}");
        s.bindings = b->dump();
    }
    read_objects(top, s);
    read_references(top, s, base_dir);
    read_study(top, j, s, base_dir);
    top.finish();
    if (s.has_stroke && s.stroke.passes > 1 && s.spec.workspace_mode != "peng_moving")
        top.fail("stroke.passes", "several passes move the workspace with Peng's technique: set workspace.mode to "
                                  "\"peng_moving\" or use one pass");
    s.stroke.workspace_scale = s.spec.workspace_scale;
    return s;
}

RunScene load_run_scene(const std::string& path_in) {
    const std::string path = path_in.empty() ? default_scene_path() : path_in;
    return run_scene_from_json(read_scene_json(path), path, fs::path(path).parent_path().string());
}

std::string default_scene_path() { return bundled_asset("default_scene.json", "scene", "pass a SCENE file"); }

}  // namespace tridex::app
