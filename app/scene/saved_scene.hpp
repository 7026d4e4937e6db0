// app/scene/saved_scene.hpp - the scene file that opens a saved session again: its saved model and every object
// beside it.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "app/scene/session_spec.hpp"

namespace tridex::app {

/// Whether a saved session needs its scene beside the model to open as it was: objects beside the workpiece, several
/// workpieces, or a posed workpiece (a .tdx holds the model in its own frame, not where the scene put it).
/// `pose`: the workpiece's pose now (the scene's, or where the tool placed it).
bool needs_saved_scene(const SessionSpec& spec, const Pose& pose);

/// Where the scene of a saved model goes: beside it, its name's extension replaced by ".scene.json"
/// (out/carved.tdx -> out/carved.scene.json).
std::string saved_scene_path(const std::string& model_path);

/// The scene that opens a saved session again: the session's scene (`scene`, the scene file's JSON; an empty object
/// for the built-in default) with its workpiece replaced by {"model": the saved model's file name, beside the scene}
/// (with "position_m", "axis" and "angle_deg" for a posed workpiece: its centre where `pose` puts it, and its turn),
/// its "references" by the session's (`spec.references`, mesh paths absolute, the turn as axis and angle), its scripts
/// ("stroke", "keys", "cursor") dropped ("stroke": "none": the new session waits for the hand), and its other relative
/// paths (tool.mesh, device.key_file, relative to `scene_dir`) made absolute, so it opens from its own folder.
/// With several workpieces (spec.more_workpieces), "workpieces" instead: the k-th's model is
/// path_for_workpiece(model_path, k) and its pose more_poses[k-1] (its spec's pose when more_poses is shorter).
nlohmann::json saved_scene_json(nlohmann::json scene, const std::string& scene_dir, const std::string& model_path,
                                const SessionSpec& spec, const Pose& pose = Pose{}, const std::vector<Pose>& more_poses = {});

/// Writes saved_scene_json for the scene file `scene_path` ("" or "<built-in>": the built-in default) to
/// saved_scene_path(model_path), atomically (a temporary file renamed). Throws tridex::Error naming the file when the
/// scene cannot be read or the file cannot be written.
std::string write_saved_scene(const std::string& scene_path, const std::string& model_path, const SessionSpec& spec,
                              const Pose& pose, const std::vector<Pose>& more_poses = {});

}  // namespace tridex::app
