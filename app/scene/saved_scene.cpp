// app/scene/saved_scene.cpp - the scene of a saved session: its model and its reference objects.
#include "app/scene/saved_scene.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "app/scene/workpiece_list.hpp"
#include "app/support/json_file.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace tridex::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A path field of `block` made absolute against `dir` when it is relative.
void absolute_field(json& block, const char* name, const std::string& dir) {
    if (!block.is_object() || !block.contains(name) || !block[name].is_string()) return;
    const fs::path p(block[name].get<std::string>());
    if (p.is_relative()) block[name] = (fs::absolute(fs::path(dir) / p)).lexically_normal().string();
}

// A turn as the scene writes it: "axis" and "angle_deg" (the short way round, so angle_deg stays in [-180, 180]).
void put_turn(json& j, const Quat& turn) {
    const Quat q = glm::normalize(turn);
    const double w = std::clamp(q.w, -1.0, 1.0);
    double angle = glm::degrees(2.0 * std::acos(w));
    const double s = std::sqrt(std::max(0.0, 1.0 - w * w));
    Vec3 axis = s > 1e-12 ? Vec3(q.x, q.y, q.z) / s : Vec3(0.0, 1.0, 0.0);
    if (angle > 180.0) {  // the same turn, the short way round
        angle = 360.0 - angle;
        axis = -axis;
    }
    j["axis"] = {axis.x, axis.y, axis.z};
    j["angle_deg"] = angle;
}

json reference_scene_json(const ReferenceSpec& r) {
    json j{{"name", r.name},
           {"mesh", r.mesh_path},
           {"size_m", r.size_m},
           {"position_m", {r.position_m.x, r.position_m.y, r.position_m.z}},
           {"stiffness_n_per_m", r.stiffness_n_per_m},
           {"colour", {r.colour.x, r.colour.y, r.colour.z, r.alpha}}};
    put_turn(j, r.orientation);
    if (r.grid_cell_m > 0.0) j["grid_cell_m"] = r.grid_cell_m;
    return j;
}

}  // namespace

bool needs_saved_scene(const SessionSpec& spec, const Pose& pose) {
    return !spec.references.empty() || !pose.is_identity() || !spec.more_workpieces.empty();
}

std::string saved_scene_path(const std::string& model_path) {
    fs::path p(model_path);
    p.replace_extension(".scene.json");
    return p.string();
}

json saved_scene_json(json scene, const std::string& scene_dir, const std::string& model_path, const SessionSpec& spec,
                      const Pose& pose, const std::vector<Pose>& more_poses) {
    if (!scene.is_object()) scene = json::object();
    for (const char* script : {"stroke", "keys", "cursor"}) scene.erase(script);
    scene["stroke"] = "none";
    // Each workpiece's saved model, its centre where its pose places it, and its turn.
    const auto entry = [&](std::size_t k, const Pose& at) {
        json w{{"model", fs::path(path_for_workpiece(model_path, k)).filename().string()}};
        if (!at.is_identity()) {
            const Vec3 c = at.apply(workpiece_at(spec, k).centre_m);
            w["position_m"] = {c.x, c.y, c.z};
            put_turn(w, at.orientation);
        }
        return w;
    };
    scene.erase("workpiece");
    scene.erase("workpieces");
    if (spec.more_workpieces.empty()) {
        scene["workpiece"] = entry(0, pose);
    } else {
        json all = json::array({entry(0, pose)});
        for (std::size_t k = 1; k < workpiece_count(spec); ++k)
            all.push_back(entry(k, k - 1 < more_poses.size() ? more_poses[k - 1] : workpiece_pose(spec_for_workpiece(spec, k))));
        scene["workpieces"] = all;
    }
    scene.erase("references");
    if (!spec.references.empty()) {
        json refs = json::array();
        for (const ReferenceSpec& r : spec.references) refs.push_back(reference_scene_json(r));
        scene["references"] = refs;
    }
    if (scene.contains("tool")) absolute_field(scene["tool"], "mesh", scene_dir);
    if (scene.contains("device")) absolute_field(scene["device"], "key_file", scene_dir);
    return scene;
}

std::string write_saved_scene(const std::string& scene_path, const std::string& model_path, const SessionSpec& spec,
                              const Pose& pose, const std::vector<Pose>& more_poses) {
    const bool built_in = scene_path.empty() || scene_path == "<built-in>";
    const json scene = built_in ? json::object() : read_scene_json(scene_path);
    const std::string dir = built_in ? std::string(".") : fs::path(scene_path).parent_path().string();
    const std::string out = saved_scene_path(model_path);
    try {
        write_file_atomically(out, saved_scene_json(scene, dir, model_path, spec, pose, more_poses).dump(2) + "\n");
    } catch (const Error& e) {
        throw Error(out + ": the saved scene cannot be written: " + e.what());
    }
    return out;
}

}  // namespace tridex::app
