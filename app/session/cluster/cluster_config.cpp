// app/session/cluster/cluster_config.cpp - reading a cluster config file, every field checked.
#include "app/session/cluster/cluster_config.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/session/view/tile_view.hpp"
#include "app/support/json_fields.hpp"
#include "core/error.hpp"
#include "core/text/json_refusal.hpp"

namespace tridex::app {

namespace {

using json = nlohmann::json;

// Largest |cos| between a tile's right and up edges (about 0.06 degrees from a right angle).
constexpr double kMaxCornerCos = 1e-3;

renderer::Screen region_of(const renderer::Screen& wall, double x0, double y0, double x1, double y1) {
    const Vec3 right = wall.lower_right - wall.lower_left, up = wall.upper_left - wall.lower_left;
    renderer::Screen s;
    s.lower_left = wall.lower_left + x0 * right + y0 * up;
    s.lower_right = wall.lower_left + x1 * right + y0 * up;
    s.upper_left = wall.lower_left + x0 * right + y1 * up;
    return s;
}

ViewportEye parse_eye(Fields& f, const std::string& name) {
    const std::string e = f.text(name, "both");
    if (e == "both") return ViewportEye::kBoth;
    if (e == "left") return ViewportEye::kLeft;
    if (e == "right") return ViewportEye::kRight;
    f.fail(f.path(name), "must be both, left or right, got '" + e + "'");
}

ViewportOutput parse_output(Fields& f, const std::string& name) {
    const std::string o = f.text(name, "offscreen");
    if (o == "offscreen") return ViewportOutput::kOffscreen;
    if (o == "window") return ViewportOutput::kWindow;
    if (o == "fullscreen") return ViewportOutput::kFullscreen;
    f.fail(f.path(name), "must be offscreen, window or fullscreen, got '" + o + "'");
}

// The tile's corners and its share of the wall's width and height (for the default pixel size).
renderer::Screen viewport_screen(Fields& f, const renderer::Screen& wall, double& share_w, double& share_h) {
    const json* region = f.get("region");
    const json* corners = f.get("corners");
    if ((region != nullptr) == (corners != nullptr)) f.fail(f.path("region"), "give either 'region' or 'corners'");
    if (region) {
        if (!region->is_array() || region->size() != 4)
            f.fail(f.path("region"), "must be [x0, y0, x1, y1]: fractions of the wall's width and height");
        double r[4];
        for (int k = 0; k < 4; ++k) {
            if (!(*region)[k].is_number()) f.fail(f.path("region"), "must hold 4 numbers");
            r[k] = (*region)[k].get<double>();
            if (!std::isfinite(r[k]) || r[k] < -10.0 || r[k] > 10.0) f.fail(f.path("region"), "must hold finite fractions in [-10, 10]");
        }
        if (!(r[2] > r[0]) || !(r[3] > r[1])) f.fail(f.path("region"), "must have x1 > x0 and y1 > y0");
        share_w = r[2] - r[0];
        share_h = r[3] - r[1];
        return region_of(wall, r[0], r[1], r[2], r[3]);
    }
    Fields c(*corners, f.source(), f.path("corners"));
    renderer::Screen s;
    s.lower_left = c.vec3("lower_left", Vec3(NAN));
    s.lower_right = c.vec3("lower_right", Vec3(NAN));
    s.upper_left = c.vec3("upper_left", Vec3(NAN));
    c.finish();
    for (const char* k : {"lower_left", "lower_right", "upper_left"})
        if (!c.get(k)) c.fail(c.path(k), "is missing");
    if (!(s.width() > 0.0) || !(s.height() > 0.0)) f.fail(f.path("corners"), "the tile has no area");
    const Vec3 right = s.lower_right - s.lower_left, up = s.upper_left - s.lower_left;
    if (std::abs(glm::dot(right, up)) / (glm::length(right) * glm::length(up)) > kMaxCornerCos)
        f.fail(f.path("corners"), "lower_left->lower_right and lower_left->upper_left must be at a right angle (within 0.06 degrees)");
    // Squared up within its plane, as the projection needs: upper_left moved to be exactly above lower_left.
    const Vec3 vr = glm::normalize(right);
    s.upper_left = s.lower_left + (up - glm::dot(up, vr) * vr);
    share_w = s.width() / wall.width();
    share_h = s.height() / wall.height();
    return s;
}

ClusterViewport read_viewport(const json& j, const std::string& source, const std::string& prefix,
                              const renderer::DisplayConfig& display) {
    Fields f(j, source, prefix);
    ClusterViewport v;
    v.name = f.text("name", "");
    if (v.name.empty() || v.name.size() > 64 ||
        !std::all_of(v.name.begin(), v.name.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_'; }))
        f.fail(f.path("name"), "must be 1..64 letters, digits, '-' or '_' (it names the viewport's output folder)");
    double share_w = 1.0, share_h = 1.0;
    v.screen = viewport_screen(f, display.screen, share_w, share_h);
    v.width_px = f.integer("width_px", std::max(1, static_cast<int>(std::lround(display.width_px * share_w))), 1, 16384);
    v.height_px = f.integer("height_px", std::max(1, static_cast<int>(std::lround(display.height_px * share_h))), 1, 16384);
    v.eye = parse_eye(f, "eye");
    const std::string stereo = f.text("stereo", "");
    try {
        v.stereo = stereo.empty() ? display.stereo : renderer::parse_stereo_output(stereo);
    } catch (const Error& e) {
        f.fail(f.path("stereo"), e.what());
    }
    if (v.eye != ViewportEye::kBoth) v.stereo = renderer::StereoOutput::kMono;
    v.output = parse_output(f, "output");
    v.monitor = f.integer("monitor", 0, 0, 63);
    v.swap_eyes = f.boolean("swap_eyes", display.swap_eyes);
    v.anaglyph = display.anaglyph;
    v.refresh_hz = display.refresh_hz;
    f.finish();
    return v;
}

}  // namespace

const ClusterRank* ClusterConfig::find(int rank) const {
    for (const ClusterRank& r : ranks)
        if (r.rank == rank) return &r;
    return nullptr;
}

ClusterConfig parse_cluster_config(const std::string& text, const std::string& source, const renderer::DisplayConfig& display) {
    json j;
    try {
        j = json::parse(text);
    } catch (const json::exception& e) {  // the line, column and what was expected; 1e400 and its field
        throw Error(source + ": not valid JSON: " + json_refusal<json>(text, e));
    }
    Fields f(j, source, "");
    ClusterConfig c;
    c.source = source;
    c.check_every_frames = f.integer("check_every_frames", c.check_every_frames, 1, 100000);
    c.timeout_s = f.number("timeout_s", c.timeout_s, 0.0, 3600.0, true);
    c.start_timeout_s = f.number("start_timeout_s", c.start_timeout_s, 0.0, 3600.0, true);
    c.lod = f.text("lod", c.lod);
    try {
        (void)lod_choice(c.lod);
    } catch (const Error& e) {
        f.fail(f.path("lod"), e.what());
    }
    c.startup = f.text("startup", c.startup);
    if (c.startup != "coarse" && c.startup != "full")
        f.fail(f.path("startup"), "must be coarse or full, got '" + c.startup + "'");
    c.stroke_contour = f.text("stroke_contour", c.stroke_contour);
    if (c.stroke_contour != "coarse" && c.stroke_contour != "full")
        f.fail(f.path("stroke_contour"), "must be coarse or full, got '" + c.stroke_contour + "'");
    c.key_file = f.text("key_file", "");
    if (!c.key_file.empty() && std::filesystem::path(c.key_file).is_relative())
        c.key_file = (std::filesystem::path(source).parent_path() / c.key_file).string();
    c.passphrase_env = f.text("passphrase_env", "");
    if (!c.key_file.empty() && !c.passphrase_env.empty()) f.fail("passphrase_env", "give key_file or passphrase_env, not both");
    const json* ranks = f.get("ranks");
    if (!ranks || !ranks->is_array() || ranks->empty()) f.fail("ranks", "must be a non-empty array of render ranks");
    std::set<std::string> names;
    for (std::size_t i = 0; i < ranks->size(); ++i) {
        const std::string prefix = "ranks[" + std::to_string(i) + "]";
        Fields r((*ranks)[i], source, prefix);
        ClusterRank cr;
        cr.rank = r.integer("rank", 0, 1, 4096);
        if (cr.rank == 0) r.fail(r.path("rank"), "is missing (render ranks are 1, 2, ...; rank 0 runs the session)");
        const json* vps = r.get("viewports");
        if (!vps || !vps->is_array() || vps->empty()) r.fail(r.path("viewports"), "must be a non-empty array");
        for (std::size_t k = 0; k < vps->size(); ++k) {
            ClusterViewport v = read_viewport((*vps)[k], source, prefix + ".viewports[" + std::to_string(k) + "]", display);
            if (!names.insert(v.name).second)
                r.fail(r.path("viewports[" + std::to_string(k) + "].name"), "'" + v.name + "' names another viewport too");
            cr.viewports.push_back(std::move(v));
        }
        r.finish();
        c.ranks.push_back(std::move(cr));
    }
    f.finish();
    std::sort(c.ranks.begin(), c.ranks.end(), [](const ClusterRank& a, const ClusterRank& b) { return a.rank < b.rank; });
    for (std::size_t i = 0; i < c.ranks.size(); ++i)
        if (c.ranks[i].rank != static_cast<int>(i) + 1)
            f.fail("ranks", "render ranks must be 1.." + std::to_string(c.ranks.size()) + ", each once; rank " +
                                std::to_string(i + 1) + " is " + (c.ranks[i].rank < static_cast<int>(i) + 1 ? "given twice" : "missing"));
    return c;
}

ClusterConfig read_cluster_config(const std::string& path, const renderer::DisplayConfig& display) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot read the cluster config");
    std::ostringstream s;
    s << in.rdbuf();
    return parse_cluster_config(s.str(), path, display);
}

}  // namespace tridex::app
