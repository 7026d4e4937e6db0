// app/scene/elastic_scene.cpp - reading and checking the scene of `tridex demo --elastic`.
#include "app/scene/elastic_scene.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "app/support/assets.hpp"
#include "app/support/json_fields.hpp"
#include "app/support/json_file.hpp"
#include "core/error.hpp"
#include "core/format.hpp"

namespace tridex::app {

namespace {

using nlohmann::json;

SceneSphere sphere_of(const json& j, const std::string& source, const std::string& prefix) {
    Fields f(j, source, prefix);
    SceneSphere o;
    o.name = f.text("name", prefix);
    const std::string shape = f.text("shape", "sphere");
    if (shape != "sphere") f.fail(f.path("shape"), "'" + shape + "' is not one of sphere");
    o.elastic = f.boolean("elastic", true);
    o.sphere.centre_m = f.vec3("centre_m", Vec3(0.0, 0.0, 0.3));
    o.sphere.radius_m = f.number("radius_m", 0.03, 0.0, 10.0, true);
    o.sphere.stiffness_n_per_m = f.number("stiffness_n_per_m", 300.0, 0.0, 1e5, true);
    o.sphere.influence_m = f.number("influence_radius_m", 0.5 * o.sphere.radius_m, 0.0, o.sphere.radius_m, true);
    f.rgba("colour", o.colour, o.alpha);
    f.finish();
    haptics::validate(o.sphere, source + ": " + prefix);
    return o;
}

}  // namespace

std::vector<SceneSphere> scene_spheres_from_json(const json& objects, const std::string& source) {
    if (!objects.is_array() || objects.empty() || objects.size() > 16)
        throw Error(source + ": field 'objects': must be an array of 1 to 16 objects");
    std::vector<SceneSphere> out;
    for (std::size_t i = 0; i < objects.size(); ++i)
        out.push_back(sphere_of(objects[i], source, "objects[" + std::to_string(i) + "]"));
    return out;
}

ElasticScene elastic_scene_from_json(const json& j, const std::string& source) {
    ElasticScene s;
    s.source = source;
    Fields top(j, source, "");
    const json* objects = top.get("objects");
    if (!objects) top.fail("objects", "missing: the scene needs at least one object to press");
    s.objects = scene_spheres_from_json(*objects, source);
    if (const json* t = top.get("tool")) {
        Fields f(*t, source, "tool");
        const std::string shape = f.text("shape", "ball");
        if (shape != "ball") f.fail("tool.shape", "'" + shape + "' is not one of ball (an elastic press uses a ball)");
        s.tool_radius_m = f.number("radius_m", s.tool_radius_m, 0.0005, 0.05);
        s.points = f.integer("points", s.points, 1, haptics::kMaxToolPoints);
        if (s.points == 2) f.fail("tool.points", "must be 1 (one ball HIP) or 3..64 (an interaction mesh), got 2");
        f.finish();
    }
    s.max_force_n = top.number("max_force_n", s.max_force_n, 0.0, 100.0, true);
    int first_elastic = -1;
    for (std::size_t i = 0; i < s.objects.size() && first_elastic < 0; ++i)
        if (s.objects[i].elastic) first_elastic = static_cast<int>(i);
    s.press.object = std::max(first_elastic, 0);
    if (const json* p = top.get("press")) {
        Fields f(*p, source, "press");
        s.press.object = f.integer("object", s.press.object, 0, static_cast<int>(s.objects.size()) - 1);
        const Vec3 d = f.vec3("direction", s.press.direction);
        if (!(glm::length(d) > 1e-9)) f.fail("press.direction", "must not be zero");
        s.press.direction = glm::normalize(d);
        if (const json* depths = f.get("depths_m")) {
            if (!depths->is_array() || depths->empty() || depths->size() > 32)
                f.fail("press.depths_m", "must be an array of 1 to 32 numbers (m)");
            s.press.depths_m.clear();
            for (const json& v : *depths) {
                if (!v.is_number()) f.fail("press.depths_m", "must be an array of numbers (m)");
                s.press.depths_m.push_back(v.get<double>());
            }
        }
        s.press.speed_m_s = f.number("speed_m_s", s.press.speed_m_s, 0.001, 1.0);
        s.press.hold_s = f.number("hold_s", s.press.hold_s, 0.0, 10.0);
        s.press.clearance_m = f.number("clearance_m", s.press.clearance_m, 0.0, 0.5);
        f.finish();
    }
    top.finish();
    const SceneSphere& target = s.objects[static_cast<std::size_t>(s.press.object)];
    if (!target.elastic)
        top.fail("press.object", "objects[" + std::to_string(s.press.object) + "]" +
                                     (target.name.rfind("objects[", 0) == 0 ? "" : " ('" + target.name + "')") +
                                     " is not elastic; press an object with \"elastic\": true");
    double last = 0.0;
    for (std::size_t i = 0; i < s.press.depths_m.size(); ++i) {
        const double d = s.press.depths_m[i];
        if (!(std::isfinite(d) && d > last && d <= target.sphere.radius_m))
            top.fail("press.depths_m[" + std::to_string(i) + "]",
                     "must be larger than the depth before it (" + format_number(last) + ") and at most the object's "
                     "radius (" + format_number(target.sphere.radius_m) + " m), got " + format_number(d));
        last = d;
    }
    return s;
}

ElasticScene load_elastic_scene(const std::string& path_in) {
    const std::string path =
        path_in.empty() ? bundled_asset("squeeze_ball_scene.json", "elastic scene", "pass --scene FILE") : path_in;
    return elastic_scene_from_json(read_scene_json(path), path);
}

}  // namespace tridex::app
