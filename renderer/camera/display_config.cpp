// renderer/camera/display_config.cpp - DisplayConfig presets, validation and JSON load/save.
#include "renderer/camera/display_config.hpp"

#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/text/json_refusal.hpp"
#include "core/text/printable.hpp"

namespace tridex::renderer {
namespace {

using nlohmann::json;

// A field path or reason may quote the file's text (a key, a name): made printable, the message stays one line.
[[noreturn]] void fail(const std::string& source, const std::string& field, const std::string& what) {
    throw Error(source + ": field '" + printable(field, 120) + "': " + printable(what, 400));
}

std::string num(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

/// |cos| of the angle between the screen's right and up edges; NaN-free for non-degenerate corners.
double corner_cosine(const Screen& s) {
    const Vec3 right = s.lower_right - s.lower_left, up = s.upper_left - s.lower_left;
    return std::abs(glm::dot(right, up)) / (glm::length(right) * glm::length(up));
}

void validate_screen(const Screen& s, const std::string& source, double max_cos) {
    const std::pair<const char*, const Vec3*> corners[] = {
        {"screen.lower_left", &s.lower_left},
        {"screen.lower_right", &s.lower_right},
        {"screen.upper_left", &s.upper_left}};
    for (const auto& [name, p] : corners)
        if (!is_finite(*p)) fail(source, name, "corner coordinates must be finite (m)");
    if (!(s.width() > 0.0)) fail(source, "screen.lower_right", "coincides with lower_left (zero screen width)");
    if (!(s.height() > 0.0)) fail(source, "screen.upper_left", "coincides with lower_left (zero screen height)");
    const double c = corner_cosine(s);
    if (!(c <= max_cos))
        fail(source, "screen.upper_left",
             "the edges lower_left->lower_right and lower_left->upper_left are not at a right angle (|cos| = " +
                 num(c) + ", at most " + num(max_cos) + ")");
}

/// Moves upper_left within the screen plane so that the up edge is perpendicular to the right edge.
Screen squared_up(Screen s) {
    const Vec3 vr = glm::normalize(s.lower_right - s.lower_left);
    const Vec3 up = s.upper_left - s.lower_left;
    s.upper_left = s.lower_left + (up - glm::dot(up, vr) * vr);
    return s;
}

Vec3 read_vec3(const json& j, const std::string& source, const std::string& field) {
    if (!j.is_array() || j.size() != 3) fail(source, field, "expected an array of 3 numbers (m)");
    Vec3 v{0.0};
    for (int k = 0; k < 3; ++k) {
        if (!j[k].is_number()) fail(source, field, "expected an array of 3 numbers (m)");
        v[k] = j[k].get<double>();
    }
    if (!is_finite(v)) fail(source, field, "coordinates must be finite (m)");
    return v;
}

double read_number(const json& j, const std::string& source, const std::string& field) {
    if (!j.is_number()) fail(source, field, "expected a number");
    return j.get<double>();
}

void validate_pose(const Pose& p, const std::string& source, const std::string& field) {
    if (!is_finite(p.position)) fail(source, field + ".position_m", "coordinates must be finite (m)");
    if (!is_unit(p.orientation))
        fail(source, field + ".orientation_wxyz", "must be a unit quaternion [w, x, y, z] (|q| = 1 within 1e-6)");
}

Pose read_pose(const json& j, const std::string& source, const std::string& field) {
    if (!j.is_object()) fail(source, field, "expected an object with position_m and orientation_wxyz");
    Pose p;
    for (const auto& [key, value] : j.items()) {
        if (key == "position_m") {
            p.position = read_vec3(value, source, field + ".position_m");
        } else if (key == "orientation_wxyz") {
            const std::string f = field + ".orientation_wxyz";
            if (!value.is_array() || value.size() != 4) fail(source, f, "expected an array of 4 numbers [w, x, y, z]");
            double q[4];
            for (int k = 0; k < 4; ++k) {
                if (!value[k].is_number()) fail(source, f, "expected an array of 4 numbers [w, x, y, z]");
                q[k] = value[k].get<double>();
            }
            p.orientation = Quat(q[0], q[1], q[2], q[3]);
        } else {
            fail(source, field + "." + key, "unknown field (valid: position_m, orientation_wxyz)");
        }
    }
    validate_pose(p, source, field);
    return p;
}

void read_tracking(const json& j, const std::string& source, DisplayConfig& c) {
    if (!j.is_object()) fail(source, "tracking", "expected an object with tracker_to_wall and/or head_to_eyes");
    for (const auto& [key, value] : j.items()) {
        if (key == "tracker_to_wall")
            c.tracker_to_wall = read_pose(value, source, "tracking.tracker_to_wall");
        else if (key == "head_to_eyes")
            c.head_to_eyes = read_pose(value, source, "tracking.head_to_eyes");
        else
            fail(source, "tracking." + key, "unknown field (valid: tracker_to_wall, head_to_eyes)");
    }
}

std::string read_string(const json& j, const std::string& source, const std::string& field) {
    if (!j.is_string()) fail(source, field, "expected a string");
    return j.get<std::string>();
}

Screen screen_preset(const std::string& name, const std::string& source, const std::string& field) {
    if (name == "powerwall") return Screen::powerwall();
    if (name == "desktop-monitor") return Screen::desktop_monitor();
    fail(source, field, "unknown screen '" + name + "'; valid: powerwall, desktop-monitor, or an object with corners");
}

Screen read_screen(const json& j, const std::string& source) {
    if (j.is_string()) return screen_preset(j.get<std::string>(), source, "screen");
    if (!j.is_object())
        fail(source, "screen", "expected a preset name or an object with lower_left, lower_right, upper_left");
    for (const auto& [key, value] : j.items()) {
        (void)value;
        if (key != "lower_left" && key != "lower_right" && key != "upper_left")
            fail(source, "screen." + key, "unknown field (valid: lower_left, lower_right, upper_left)");
    }
    Screen s;
    const std::pair<const char*, Vec3*> corners[] = {
        {"lower_left", &s.lower_left}, {"lower_right", &s.lower_right}, {"upper_left", &s.upper_left}};
    for (const auto& [name, p] : corners) {
        const std::string field = std::string("screen.") + name;
        if (!j.contains(name)) fail(source, field, "missing (every corner must be given, m)");
        *p = read_vec3(j.at(name), source, field);
    }
    validate_screen(s, source, 0.01);
    return squared_up(s);
}

}  // namespace

DisplayConfig DisplayConfig::powerwall() {
    DisplayConfig c;
    c.screen = Screen::powerwall();
    c.stereo = StereoOutput::kFrameSequential;
    c.refresh_hz = 120.0;
    c.width_px = 1280;
    c.height_px = 960;
    c.default_head_m = Vec3(0.0, 0.0, 2.0);
    return c;
}

DisplayConfig DisplayConfig::desktop() { return DisplayConfig{}; }

void validate_display_config(const DisplayConfig& c, const std::string& source) {
    validate_screen(c.screen, source, 1e-6);
    if (!std::isfinite(c.eye_separation_m) || c.eye_separation_m < 0.0 || c.eye_separation_m > 0.2)
        fail(source, "eye_separation_m", "must be in [0, 0.2] m (got " + num(c.eye_separation_m) + ")");
    if (!std::isfinite(c.refresh_hz) || !(c.refresh_hz > 0.0) || c.refresh_hz > 1000.0)
        fail(source, "refresh_hz", "must be in (0, 1000] Hz (got " + num(c.refresh_hz) + ")");
    if (c.width_px < 1 || c.width_px > 16384 || c.height_px < 1 || c.height_px > 16384)
        fail(source, "resolution", "width and height must be in 1..16384 pixels (got " + std::to_string(c.width_px) +
                                       "x" + std::to_string(c.height_px) + ")");
    if (!is_finite(c.default_head_m)) fail(source, "default_head_m", "coordinates must be finite (m)");
    validate_pose(c.tracker_to_wall, source, "tracking.tracker_to_wall");
    validate_pose(c.head_to_eyes, source, "tracking.head_to_eyes");
    const Vec3 vr = glm::normalize(c.screen.lower_right - c.screen.lower_left);
    const Vec3 vu = glm::normalize(c.screen.upper_left - c.screen.lower_left);
    const double d = glm::dot(c.default_head_m - c.screen.lower_left, glm::normalize(glm::cross(vr, vu)));
    if (!(d > 0.0))
        fail(source, "default_head_m", "must be in front of the screen (distance along the screen normal " + num(d) +
                                           " m)");
}

DisplayConfig display_config_from_json(const json& j, const std::string& source) {
    if (!j.is_object()) throw Error(source + ": a display config must be a JSON object");
    static const char* const kFields[] = {"preset",     "screen",     "stereo",          "anaglyph",
                                          "eye_separation_m", "swap_eyes", "ambient_occlusion", "refresh_hz",
                                          "resolution", "default_head_m", "tracking"};
    for (const auto& [key, value] : j.items()) {
        (void)value;
        bool known = false;
        for (const char* f : kFields) known = known || key == f;
        if (!known)
            fail(source, key, "unknown field (valid: preset, screen, stereo, anaglyph, eye_separation_m, swap_eyes, "
                              "ambient_occlusion, refresh_hz, resolution, default_head_m, tracking)");
    }
    DisplayConfig c;
    if (j.contains("preset")) {
        const std::string p = read_string(j.at("preset"), source, "preset");
        if (p == "powerwall")
            c = DisplayConfig::powerwall();
        else if (p != "desktop")
            fail(source, "preset", "unknown preset '" + p + "'; valid: desktop, powerwall");
    }
    if (j.contains("screen")) c.screen = read_screen(j.at("screen"), source);
    if (j.contains("stereo")) {
        const std::string name = read_string(j.at("stereo"), source, "stereo");
        try {
            c.stereo = parse_stereo_output(name);
        } catch (const Error& e) {
            fail(source, "stereo", e.what());
        }
    }
    if (j.contains("anaglyph")) {
        const std::string name = read_string(j.at("anaglyph"), source, "anaglyph");
        try {
            c.anaglyph = parse_anaglyph_method(name);
        } catch (const Error& e) {
            fail(source, "anaglyph", e.what());
        }
    }
    if (j.contains("eye_separation_m"))
        c.eye_separation_m = read_number(j.at("eye_separation_m"), source, "eye_separation_m");
    if (j.contains("swap_eyes")) {
        if (!j.at("swap_eyes").is_boolean()) fail(source, "swap_eyes", "expected true or false");
        c.swap_eyes = j.at("swap_eyes").get<bool>();
    }
    if (j.contains("ambient_occlusion")) {
        if (!j.at("ambient_occlusion").is_boolean()) fail(source, "ambient_occlusion", "expected true or false");
        c.ambient_occlusion = j.at("ambient_occlusion").get<bool>();
    }
    if (j.contains("refresh_hz")) c.refresh_hz = read_number(j.at("refresh_hz"), source, "refresh_hz");
    if (j.contains("resolution")) {
        const json& r = j.at("resolution");
        if (!r.is_array() || r.size() != 2 || !r[0].is_number_integer() || !r[1].is_number_integer())
            fail(source, "resolution", "expected [width, height] in whole pixels");
        const auto w = r[0].get<long long>(), h = r[1].get<long long>();
        if (w < 1 || w > 16384 || h < 1 || h > 16384)
            fail(source, "resolution", "width and height must be in 1..16384 pixels (got " + std::to_string(w) + "x" +
                                           std::to_string(h) + ")");
        c.width_px = static_cast<int>(w);
        c.height_px = static_cast<int>(h);
        c.resolution_given = true;
    }
    if (j.contains("default_head_m")) c.default_head_m = read_vec3(j.at("default_head_m"), source, "default_head_m");
    if (j.contains("tracking")) read_tracking(j.at("tracking"), source, c);
    validate_display_config(c, source);
    return c;
}

json display_config_to_json(const DisplayConfig& c) {
    validate_display_config(c, "display_config_to_json");
    const auto v3 = [](const Vec3& v) { return json::array({v.x, v.y, v.z}); };
    json j;
    j["screen"] = {{"lower_left", v3(c.screen.lower_left)},
                   {"lower_right", v3(c.screen.lower_right)},
                   {"upper_left", v3(c.screen.upper_left)}};
    j["stereo"] = std::string(to_string(c.stereo));
    j["anaglyph"] = std::string(to_string(c.anaglyph));
    j["eye_separation_m"] = c.eye_separation_m;
    j["swap_eyes"] = c.swap_eyes;
    j["ambient_occlusion"] = c.ambient_occlusion;
    j["refresh_hz"] = c.refresh_hz;
    j["resolution"] = json::array({c.width_px, c.height_px});
    j["default_head_m"] = v3(c.default_head_m);
    const auto pose = [&v3](const Pose& p) {
        const Quat& q = p.orientation;
        return json{{"position_m", v3(p.position)}, {"orientation_wxyz", json::array({q.w, q.x, q.y, q.z})}};
    };
    j["tracking"] = {{"tracker_to_wall", pose(c.tracker_to_wall)}, {"head_to_eyes", pose(c.head_to_eyes)}};
    return j;
}

DisplayConfig load_display_config(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open the display config file");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    json j;
    try {
        j = json::parse(text);
    } catch (const json::exception& e) {  // the line, column and what was expected; 1e400 and its field
        throw Error(path + ": not valid JSON: " + json_refusal<json>(text, e));
    }
    return display_config_from_json(j, path);
}

void save_display_config(const std::string& path, const DisplayConfig& config) {
    validate_display_config(config, path);
    const json j = display_config_to_json(config);
    std::ofstream out(path);
    if (!out) throw Error(path + ": cannot write the display config file");
    out << j.dump(2) << '\n';
    if (!out) throw Error(path + ": cannot write the display config file");
}

}  // namespace tridex::renderer
