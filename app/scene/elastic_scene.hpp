// app/scene/elastic_scene.hpp - the scene of `tridex demo --elastic`: elastic (and rigid) objects, the tool that presses
// them, and the scripted press, read from a JSON file with every field checked.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "core/math.hpp"
#include "core/tool_shape.hpp"
#include "haptics/elastic_object.hpp"

namespace tridex::app {

/// One object of the scene: a sphere, felt through its undeformed surface; an elastic one is drawn dented within its
/// radius of influence while the tool presses it and springs back when released (haptics/elastic_object.hpp); a rigid
/// one ("elastic": false) is felt the same way and never drawn dented.
struct SceneSphere {
    std::string name;                   ///< for messages and the report
    haptics::ElasticSphere sphere;      ///< centre, radius, stiffness, radius of influence (SI)
    bool elastic = true;                ///< false: a rigid object (no drawn deformation)
    Vec3 colour{0.85, 0.32, 0.25};      ///< linear RGB, each in [0, 1]
    double alpha = 1.0;                 ///< opacity, [0, 1]
};

/// The scripted press: the hand approaches the target object along `direction`, presses in to each depth of
/// `depths_m` in turn (measured from first contact of the tool with the undeformed surface), holds each for hold_s,
/// then withdraws to where it started and holds there.
struct ScenePress {
    int object = 0;                           ///< index into objects of the object pressed
    Vec3 direction{0.0, -1.0, 0.0};           ///< unit press direction (world); the tool meets the surface point
                                              ///< centre - radius * direction
    std::vector<double> depths_m{0.002, 0.004, 0.006, 0.008};  ///< increasing, each in (0, radius], m
    double speed_m_s = 0.02;                  ///< hand speed between holds, m/s
    double hold_s = 0.3;                      ///< time at each depth, s
    double clearance_m = 0.01;                ///< gap between the tool and the surface at the start, m
};

/// Everything `tridex demo --elastic` presses and draws (SI units; world frame of DESIGN.md).
///
/// JSON form (unknown fields refused; defaults as on the structs above):
/// ```
/// { "objects": [ { "name": "squeeze_ball", "shape": "sphere", "elastic": true,
///                  "centre_m": [0, 0, 0.3], "radius_m": 0.03, "stiffness_n_per_m": 300,
///                  "influence_radius_m": 0.015,                  // Popescu 3.3 radius of influence, <= radius_m
///                  "colour": [0.85, 0.32, 0.25, 1.0] } ],        // RGBA, alpha optional
///   "tool": { "shape": "ball", "radius_m": 0.006, "points": 32 }, // 1 = one ball HIP; 3..64 an interaction mesh
///   "press": { "object": 0, "direction": [0, -1, 0], "depths_m": [0.002, 0.004, 0.006, 0.008],
///              "speed_m_s": 0.02, "hold_s": 0.3, "clearance_m": 0.01 },
///   "max_force_n": 3.3 }                                          // the device's force limit, N
/// ```
struct ElasticScene {
    std::string source = "<built-in>";  ///< the file it was read from
    std::vector<SceneSphere> objects;   ///< at least one; the pressed one must be elastic
    double tool_radius_m = 0.006;       ///< the ball tool's radius, m
    int points = 32;                    ///< 1: one ball point; 3..64: an interaction mesh over the ball
    ScenePress press;
    double max_force_n = 3.3;           ///< force limit, N (an Omni-class device)
};

/// Reads a scene's "objects" array (`objects`, the field's JSON; each entry in the form on ElasticScene) from `source`:
/// 1 to 16 spheres. Throws tridex::Error "<source>: field 'objects[i].<name>': <what is wrong>" for a wrong type, an
/// out-of-range or non-finite value, an unknown shape or field, or an empty or too long array.
std::vector<SceneSphere> scene_spheres_from_json(const nlohmann::json& objects, const std::string& source);

/// Reads the scene from parsed JSON (form on ElasticScene). Throws tridex::Error "<source>: field '<path>': <what is
/// wrong>" for a wrong type, an out-of-range or non-finite value, an unknown name or field, a missing "objects", a
/// pressed object that is not elastic, or depths that do not increase.
ElasticScene elastic_scene_from_json(const nlohmann::json& json, const std::string& source);

/// Loads a scene file; "" loads the bundled assets/squeeze_ball_scene.json. Throws tridex::Error naming the file when
/// it cannot be read or is not JSON, and as elastic_scene_from_json for bad fields.
ElasticScene load_elastic_scene(const std::string& path);

}  // namespace tridex::app
