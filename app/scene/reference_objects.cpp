// app/scene/reference_objects.cpp - reading, keeping and loading a scene's reference objects.
#include "app/scene/reference_objects.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "app/scene/session_spec.hpp"
#include "app/support/json_fields.hpp"
#include "core/error.hpp"
#include "core/format.hpp"

namespace tridex::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

ReferenceSpec reference_of(const json& j, const std::string& source, const std::string& prefix,
                           const std::string& base_dir) {
    Fields f(j, source, prefix);
    ReferenceSpec r;
    r.name = f.text("name", prefix);
    const std::string mesh = f.text("mesh", "");
    if (mesh.empty()) f.fail(f.path("mesh"), "a reference object needs its closed mesh file");
    const fs::path p = fs::path(mesh).is_absolute() ? fs::path(mesh) : fs::path(base_dir) / mesh;
    if (!fs::is_regular_file(p)) f.fail(f.path("mesh"), "no such file: " + p.string());
    r.mesh_path = fs::absolute(p).lexically_normal().string();  // a recording replays from any folder
    std::tie(r.mesh_crc32, r.mesh_bytes) = file_crc32(r.mesh_path);
    r.size_m = f.number("size_m", r.size_m, 0.0, 10.0, true);
    r.position_m = f.vec3("position_m", r.position_m);
    for (int a = 0; a < 3; ++a)
        if (!(std::abs(r.position_m[a]) <= 1e3)) f.fail(f.path("position_m"), "each coordinate must be in [-1000, 1000] m");
    r.orientation = f.turn();
    r.stiffness_n_per_m = f.number("stiffness_n_per_m", r.stiffness_n_per_m, 0.0, 1e5, true);
    r.grid_cell_m = f.number("grid_cell_m", 0.0, 0.0, r.size_m / 8.0);
    f.rgba("colour", r.colour, r.alpha);
    f.finish();
    return r;
}

}  // namespace

std::vector<ReferenceSpec> references_from_scene_json(const json& refs, const std::string& source,
                                                      const std::string& base_dir) {
    if (!refs.is_array() || refs.empty() || refs.size() > kMaxSceneReferences)
        throw Error(source + ": field 'references': must be an array of 1 to " + std::to_string(kMaxSceneReferences) +
                    " objects");
    std::vector<ReferenceSpec> out;
    for (std::size_t i = 0; i < refs.size(); ++i)
        out.push_back(reference_of(refs[i], source, "references[" + std::to_string(i) + "]", base_dir));
    return out;
}

json reference_settings_json(const ReferenceSpec& r) {
    const Quat& q = r.orientation;
    return {{"name", r.name},
            {"mesh", r.mesh_path},
            {"mesh_crc32", r.mesh_crc32},
            {"mesh_bytes", r.mesh_bytes},
            {"size_m", r.size_m},
            {"position_m", {r.position_m.x, r.position_m.y, r.position_m.z}},
            {"orientation_wxyz", {q.w, q.x, q.y, q.z}},
            {"stiffness_n_per_m", r.stiffness_n_per_m},
            {"grid_cell_m", r.grid_cell_m},
            {"colour", {r.colour.x, r.colour.y, r.colour.z, r.alpha}}};
}

ReferenceSpec reference_from_settings_json(const json& j, const std::string& what) {
    auto bad = [&](const std::string& field, const std::string& why) { throw Error(what + "." + field + ": " + why); };
    auto num = [&](const char* field, double lo, double hi) {
        if (!j.contains(field) || !j.at(field).is_number()) bad(field, "missing or not a number");
        const double v = j.at(field).get<double>();
        if (!(std::isfinite(v) && v >= lo && v <= hi))
            bad(field, "must be in [" + format_number(lo) + ", " + format_number(hi) + "], got " + format_number(v));
        return v;
    };
    auto arr = [&](const char* field, std::size_t n) {
        if (!j.contains(field) || !j.at(field).is_array() || j.at(field).size() != n)
            bad(field, "must be an array of " + std::to_string(n) + " numbers");
        std::vector<double> v;
        for (const json& x : j.at(field)) {
            if (!x.is_number() || !std::isfinite(x.get<double>())) bad(field, "must hold finite numbers");
            v.push_back(x.get<double>());
        }
        return v;
    };
    if (!j.is_object()) bad("(entry)", "must be an object");
    ReferenceSpec r;
    if (!j.contains("name") || !j.at("name").is_string()) bad("name", "missing or not a string");
    if (!j.contains("mesh") || !j.at("mesh").is_string()) bad("mesh", "missing or not a string");
    r.name = j.at("name").get<std::string>();
    r.mesh_path = j.at("mesh").get<std::string>();
    r.mesh_crc32 = static_cast<std::uint32_t>(num("mesh_crc32", 0.0, 4294967295.0));
    r.mesh_bytes = static_cast<std::uint64_t>(num("mesh_bytes", 0.0, 1e15));
    r.size_m = num("size_m", 1e-9, 10.0);
    const std::vector<double> p = arr("position_m", 3), q = arr("orientation_wxyz", 4), c = arr("colour", 4);
    r.position_m = Vec3(p[0], p[1], p[2]);
    r.orientation = Quat(q[0], q[1], q[2], q[3]);
    const double qn = glm::length(r.orientation);
    if (!(std::abs(qn - 1.0) <= 1e-6)) bad("orientation_wxyz", "must be a unit quaternion, |q| = " + format_number(qn));
    r.stiffness_n_per_m = num("stiffness_n_per_m", 1e-9, 1e5);
    r.grid_cell_m = num("grid_cell_m", 0.0, r.size_m / 8.0);
    for (double x : c)
        if (!(x >= 0.0 && x <= 1.0)) bad("colour", "each component must be in [0, 1]");
    r.colour = Vec3(c[0], c[1], c[2]);
    r.alpha = c[3];
    return r;
}

json references_report_json(const std::vector<ReferenceSpec>& refs, const std::vector<PreparedReference>& prepared) {
    json out = json::array();
    for (std::size_t i = 0; i < refs.size() && i < prepared.size(); ++i) {
        const ReferenceSpec& r = refs[i];
        const DistanceGrid& g = *prepared[i].object.grid;
        out.push_back({{"name", r.name},
                       {"mesh", r.mesh_path},
                       {"triangles", prepared[i].mesh_m.triangles.size()},
                       {"size_m", r.size_m},
                       {"position_m", {r.position_m.x, r.position_m.y, r.position_m.z}},
                       {"grid", {{"nodes", {g.nodes[0], g.nodes[1], g.nodes[2]}}, {"cell_m", g.cell_m}, {"bytes", g.bytes()}}},
                       {"build_s", prepared[i].build_s}});
    }
    return out;
}

glm::mat4 world_from_reference(const ReferenceSpec& r) {
    const glm::dmat4 m = glm::translate(glm::dmat4(1.0), r.position_m) * glm::mat4_cast(r.orientation);
    return glm::mat4(m);
}

}  // namespace tridex::app
