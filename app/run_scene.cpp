// app/run_scene.cpp - reading and checking the scene of `tridex run`.
#include "app/run_scene.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "app/assets.hpp"
#include "app/demo.hpp"
#include "core/error.hpp"

namespace tridex::app {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string fmt(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

// The fields of one JSON object, read by name; finish() refuses the names nobody asked for.
class Fields {
public:
    Fields(const json& j, const std::string& source, const std::string& prefix)
        : j_(j), source_(source), prefix_(prefix) {
        if (!j.is_object()) fail(prefix_.empty() ? "(top level)" : prefix_, "must be a JSON object");
    }

    [[noreturn]] void fail(const std::string& field, const std::string& what) const {
        throw Error(source_ + ": field '" + field + "': " + what);
    }
    std::string path(const std::string& name) const { return prefix_.empty() ? name : prefix_ + "." + name; }

    const json* get(const std::string& name) {
        known_.insert(name);
        const auto it = j_.find(name);
        return it == j_.end() ? nullptr : &*it;
    }

    double number(const std::string& name, double def, double lo, double hi, bool lo_open = false) {
        const json* v = get(name);
        if (!v) return def;
        if (!v->is_number()) fail(path(name), "must be a number");
        const double x = v->get<double>();
        if (!std::isfinite(x) || x > hi || (lo_open ? x <= lo : x < lo))
            fail(path(name), "must be in " + std::string(lo_open ? "(" : "[") + fmt(lo) + ", " + fmt(hi) + "], got " +
                                 fmt(x));
        return x;
    }

    int integer(const std::string& name, int def, int lo, int hi) {
        const json* v = get(name);
        if (!v) return def;
        if (!v->is_number_integer()) fail(path(name), "must be an integer");
        const long long x = v->get<long long>();
        if (x < lo || x > hi)
            fail(path(name), "must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", got " +
                                 std::to_string(x));
        return static_cast<int>(x);
    }

    bool boolean(const std::string& name, bool def) {
        const json* v = get(name);
        if (!v) return def;
        if (!v->is_boolean()) fail(path(name), "must be true or false");
        return v->get<bool>();
    }

    std::string text(const std::string& name, const std::string& def) {
        const json* v = get(name);
        if (!v) return def;
        if (!v->is_string()) fail(path(name), "must be a string");
        return v->get<std::string>();
    }

    Vec3 vec3(const std::string& name, const Vec3& def) {
        const json* v = get(name);
        return v ? vec3_of(*v, path(name)) : def;
    }

    Vec3 vec3_of(const json& v, const std::string& field) const {
        if (!v.is_array() || v.size() != 3) fail(field, "must be an array of 3 numbers (m)");
        Vec3 out;
        for (int k = 0; k < 3; ++k) {
            if (!v[k].is_number()) fail(field, "must be an array of 3 numbers (m)");
            out[k] = v[k].get<double>();
            if (!std::isfinite(out[k])) fail(field, "must be finite");
        }
        return out;
    }

    void finish() const {
        for (auto it = j_.begin(); it != j_.end(); ++it)
            if (!known_.count(it.key())) fail(path(it.key()), "unknown field");
    }

    const std::string& source() const { return source_; }

private:
    const json& j_;
    std::string source_, prefix_;
    std::set<std::string> known_;
};

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

void read_workpiece(Fields& top, RunScene& s, const std::string& base_dir) {
    const json* w = top.get("workpiece");
    if (!w) {
        s.mesh_path = default_mesh_path();
        return;
    }
    Fields f(*w, top.source(), "workpiece");
    const std::string mesh = f.text("mesh", "");
    if (mesh.empty()) {
        s.mesh_path = default_mesh_path();
    } else {
        const fs::path p = fs::path(mesh).is_absolute() ? fs::path(mesh) : fs::path(base_dir) / mesh;
        if (!fs::is_regular_file(p)) f.fail("workpiece.mesh", "no such file: " + p.string());
        s.mesh_path = p.string();
    }
    s.resolution = f.integer("resolution", s.resolution, 8, 4096);
    s.stock_m = f.number("stock_m", s.stock_m, 0.0, 10.0, true);
    s.centre_m = f.vec3("centre_m", s.centre_m);
    f.finish();
}

void read_tool(Fields& top, RunScene& s) {
    const json* t = top.get("tool");
    if (t) {
        Fields f(*t, top.source(), "tool");
        s.tool_radius_m = f.number("radius_m", s.tool_radius_m, 0.0005, 0.25 * s.stock_m);
        s.stiffness_n_per_m = f.number("stiffness_n_per_m", s.stiffness_n_per_m, 0.0, 1e5, true);
        s.damping_n_s_per_m = f.number("damping_n_s_per_m", s.damping_n_s_per_m, 0.0, 1e3);
        f.finish();
    } else if (s.tool_radius_m > 0.25 * s.stock_m) {
        top.fail("tool.radius_m", "the default " + fmt(s.tool_radius_m) + " m exceeds a quarter of workpiece.stock_m");
    }
}

void read_workspace(Fields& top, RunScene& s) {
    const json* w = top.get("workspace");
    if (!w) return;
    Fields f(*w, top.source(), "workspace");
    const std::string mode = f.text("mode", haptics::to_string(s.workspace_mode));
    try {
        s.workspace_mode = haptics::parse_workspace_mode(mode);
    } catch (const Error& e) {
        f.fail("workspace.mode", e.what());
    }
    s.workspace_scale = f.number("scale", s.workspace_scale, 0.0, 100.0, true);
    f.finish();
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
        const std::string axis = f.text("press_axis", "z");
        if (axis != "y" && axis != "z") f.fail("stroke.press_axis", "must be \"z\" (from the viewer) or \"y\" (from above)");
        p.press_axis = axis == "y" ? 1 : 2;
        f.finish();
    }
    p.tool_radius_m = s.tool_radius_m;
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
    if (const json* o = f.get("orientation_wxyz")) s.head_pose.orientation = quat_of(f, *o, "head.orientation_wxyz");
    s.head_loop = f.boolean("loop", false);
    s.tracker_timeout_s = f.number("tracker_timeout_s", s.tracker_timeout_s, 0.0, 10.0, true);
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

}  // namespace

const char* to_string(HeadMode mode) {
    switch (mode) {
        case HeadMode::kFixed: return "fixed";
        case HeadMode::kScripted: return "scripted";
        case HeadMode::kTracker: return "tracker";
    }
    return "fixed";
}

HeadMode parse_head_mode(const std::string& name, const std::string& what) {
    for (HeadMode m : {HeadMode::kFixed, HeadMode::kScripted, HeadMode::kTracker})
        if (name == to_string(m)) return m;
    throw Error(what + ": head provider '" + name + "' is not one of fixed, scripted, tracker");
}

RunScene run_scene_from_json(const json& j, const std::string& source, const std::string& base_dir) {
    RunScene s;
    s.source = source;
    Fields top(j, source, "");
    read_workpiece(top, s, base_dir);
    read_tool(top, s);
    read_workspace(top, s);
    read_stroke(top, s);
    read_display(top, s);
    read_head(top, s);
    top.finish();
    return s;
}

RunScene load_run_scene(const std::string& path_in) {
    const std::string path = path_in.empty() ? default_scene_path() : path_in;
    std::ifstream in(path);
    if (!in) throw Error(path + ": cannot read the scene file");
    json j;
    try {
        in >> j;
    } catch (const json::parse_error& e) {
        throw Error(path + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
    }
    return run_scene_from_json(j, path, fs::path(path).parent_path().string());
}

std::string default_scene_path() { return bundled_asset("default_scene.json", "scene", "pass a SCENE file"); }

}  // namespace tridex::app
