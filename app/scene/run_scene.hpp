// app/scene/run_scene.hpp - the scene of `tridex run`: workpiece, tool, workspace, scripted stroke, display and head,
// read from a JSON file with every field checked.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "app/scene/session_spec.hpp"
#include "app/scene/stroke.hpp"
#include "core/math.hpp"
#include "core/pose.hpp"
#include "haptics/workspace_mapping.hpp"
#include "app/input/cursor_script.hpp"
#include "app/scene/elastic_scene.hpp"
#include "app/input/key_script.hpp"
#include "app/scene/study_scene.hpp"
#include "renderer/camera/display_config.hpp"
#include "renderer/camera/head_pose.hpp"

namespace tridex::app {

/// Where the viewer's head pose comes from (renderer/camera/head_pose.hpp).
enum class HeadMode {
    kFixed,     ///< [fixed] FixedHead at RunScene::head_pose (in a window: keyboard and mouse move it)
    kScripted,  ///< [scripted] ScriptedHead through RunScene::head_waypoints
    kTracker,   ///< [tracker] TrackerHead filled by a tracker driver; RunScene::head_pose until one pushes
    kDTrack,    ///< [dtrack] ART DTrack over UDP (app/input/dtrack_head.hpp); RunScene::head_pose while untracked or stale
};

/// "fixed", "scripted", "tracker" or "dtrack".
const char* to_string(HeadMode mode);
/// Inverse of to_string; throws tridex::Error "<what>: head provider 'x' is not one of fixed, scripted, tracker, dtrack".
HeadMode parse_head_mode(const std::string& name, const std::string& what);

/// A study scene in a run (app/study/): the tube, funnels and caps shown and felt as one of the three models of
/// Singapogu's thesis (4.3.2). The felt objects become the session's workpiece (app/scene/study_walls.hpp: the
/// multi-point god-object feels them), which is never drawn; the visible ones are drawn in their colours,
/// changing on contact (app/scene/study_objects.hpp). The tool is the wand: a flat end of the study scene's
/// wand radius and length with its two contact points (bottom = the flat end, top), op "none" (nothing is
/// carved). A simulated device's hand follows the scripted participant's path (app/scene/study_participant.hpp)
/// from the start cap to the end cap.
struct RunStudy {
    bool enabled = false;              ///< the scene has a "study" object
    study::StudyScene scene;           ///< the study scene file's contents
    std::string model = "test";        ///< haptic_training | visual_training | test
    std::uint32_t seed = 1;            ///< the scripted participant's seed, >= 1
    int trial = 1;                     ///< the scripted participant's trial number, >= 1
    /// End the run once both wand points have touched the end cap after touching the start cap (a test trial
    /// of the protocol, gated by the end cap).
    bool end_at_end_cap = false;
    std::string phase_line;            ///< an overlay line (the protocol's phase and what to do); "" = none
    /// A protocol's test trial: --record tags the recording (app/scene/study_recording.hpp) with this participant
    /// ID, group ("haptic" | "visual") and trial, so `tridex study analyze` reads it; "" = an untagged recording.
    std::string participant;
    std::string group;
};

/// Everything a `tridex run` session shows and sculpts (SI units; world = tracker space, m, y up, the
/// display's screen as given by its corners).
///
/// JSON form (every field optional, defaults as below; unknown fields are refused):
/// ```
/// { "workpiece": { "mesh": "bunny.off",          // relative to the scene file; default: the bundled bunny
///                  "model": "carved.tdx",         // instead of mesh: start from a saved model (relative to the
///                                                 // scene file; then no resolution, stock_m or centre_m: the
///                                                 // model decides them; tool sizes are checked against the
///                                                 // default stock_m)
///                  "resolution": 128,             // lattice cells along the longest side, 8..4096
///                  "stock_m": 0.12,               // longest side after scaling, m, (0, 10]
///                  "centre_m": [0, 0, 0.05] },    // where its bounding box is centred, m
///   "workpieces": [ {...}, {...} ],                  // instead of "workpiece": 1..8 such objects, each its own
///                                                 // model, lattice and pose (app/scene/scene_workpieces.hpp)
///   "tool": { "shape": "ball" | "flat_end" | "mesh",       // core/tool_shape.hpp
///             "radius_m": 0.006, "length_m": 0.02,            // length_m: flat_end only (default 4 radii)
///             "mesh": "tool.off", "size_m": 0.012,            // mesh only (instead of radius_m): a closed mesh
///                                                             // relative to the scene file, longest side size_m,
///                                                             // +y its axis, its tip the HIP (app/scene/tool_mesh.hpp)
///             "stiffness_n_per_m": 700, "damping_n_s_per_m": 0.5 },
///   "device": { "driver": "simulated", "profile": "omni" | "wand" | "6dof" },
///   "op": "subtract" | "union" | "paint" | "push" | "smooth" | "pull", "material": 1 | "teal", // palette id 1..7 or name
///   "materials": [ { "id": 0, "stiffness_n_per_m": 500, "damping_n_s_per_m": 0.4,
///                    "static_friction": 0.3, "dynamic_friction": 0.2 },        // contact per material id
///                  { "id": 2, "name": "teal", "colour": "#2a9d8f" }, ... ],   // names, sRGB colours (scene_materials.hpp)
///   "haptics": { "points": 1, "static_friction": 0.2, "dynamic_friction": 0.15, "cutting_force": true },
///   "workspace": { "mode": "peng_moving", "scale": 1.0 },   // haptics::parse_workspace_mode names; scale: the
///                                                          // device -> world gain in [0.01, 100] (kWorkspaceScaleMin,
///                                                          // kWorkspaceScaleMax), or "fit" (workspace_fit)
///   "stroke": { "duration_s": 3, "length_m": 0.08, "depth_m": 0.004, "clearance_m": 0.02,
///               "press_axis": "z", "workpiece": 0 }  |  "none",  // app/scene/stroke.hpp plan_stroke, on
///                                                 // that workpiece of "workpieces"
///   "cursor": [ {"t_s": 0.5, "x_px": 400, "y_px": 300, "buttons": 1}, ... ],  // device "mouse": the scripted
///                                                 // cursor (pixels of one eye's image; buttons 1 left, 2 right)
///   "display": "desktop" | "powerwall" | { display config, renderer/camera/display_config.hpp },
///   "head": { "provider": "fixed" | "scripted" | "tracker" | "dtrack",
///             "port": 5000, "body": 0, "bind_address": "0.0.0.0",  // dtrack: UDP port, head body id, listen address
///             "position_m": [x, y, z],                       // default: the display's default_head_m
///             "waypoints": [ {"t_s": 0, "position_m": [x, y, z], "orientation_wxyz": [1, 0, 0, 0]}, ... ],
///             "loop": false, "tracker_timeout_s": 0.1 },
///   "wand": { "provider": "none" | "dtrack", "port": 5000, "flystick": 0,   // DTrack Flystick (`6df2`) id
///             "bind_address": "0.0.0.0", "timeout_s": 0.1 },
///   "objects": [ { "name": "squeeze_ball", "shape": "sphere", "elastic": true, "centre_m": [x, y, z],
///                  "radius_m": 0.03, "stiffness_n_per_m": 300, "influence_radius_m": 0.015,
///                  "colour": [r, g, b, a] }, ... ],        // app/scene/elastic_scene.hpp; felt and drawn beside the workpiece
///   "references": [ { "name": "stand", "mesh": "bar.off",   // closed mesh, relative to the scene file
///                     "size_m": 0.1, "position_m": [x, y, z],    // longest side; where its box centre stands
///                     "axis": [0, 1, 0], "angle_deg": 30,        // turned about its centre
///                     "stiffness_n_per_m": 700, "grid_cell_m": 0, // 0: size_m / 96, at least 0.5 mm
///                     "colour": [r, g, b, a] }, ... ],           // app/scene/reference_objects.hpp; drawn and felt, never sculpted
///   "study": { "scene": "study_tube_scene.json",   // a study scene file (relative to the scene file), RunStudy;
///              "model": "test", "seed": 1, "trial": 1,   // then no workpiece, tool, op, haptics or stroke fields
///              "end_at_end_cap": false, "phase_line": "...",          // ... an overlay line
///              "participant": "P01", "group": "haptic" } }             // tag a --record of a test trial
/// ```
struct RunScene {
    std::string source = "<built-in>";  ///< the file it was read from (for messages and the report)
    /// What decides the sculpted result (workpiece, tool, device, op, materials, haptics); device_origin_m is
    /// set when the session is built (the stroke's centre). Scene defaults: resolution 128, stock 0.12 m
    /// centred at (0, 0, 0.05) m, a 6 mm ball.
    SessionSpec spec = default_spec();
    /// The scene defaults of `spec`.
    static SessionSpec default_spec();
    bool has_stroke = true;             ///< false: the simulated hand holds still in front of the workpiece
    bool device_named = false;          ///< the scene has a "device" block (else a window session uses the mouse)
    /// "workspace": {"scale": "fit"}: the session picks the device -> world gain so that what the hand must reach
    /// (a study's tube from cap to cap, a stroke's path, else the workpiece) fits the device's workspace: 1 when
    /// it fits already, else the smallest gain that makes it fit (app/session/run/run_sculpt.hpp fit_workspace_scale).
    bool workspace_fit = false;
    /// Keys pressed at given device times ("keys": [{"t_s": 4.0, "press": "ctrl+z"}], in time order), handled
    /// like a window's keys (undo, redo, save, ...), offscreen too.
    std::vector<ScriptedKey> keys;
    /// The scripted mouse cursor of a mouse-stylus session ("cursor"; device "mouse"), in device time.
    CursorScript cursor;
    /// The driver's own numeric options that the scene's "device" block set (DriverCapabilities::options: the 3D
    /// mouse's gains and dead zone, ...), by name, SI units, checked against the driver's ranges. They shape the
    /// hand, not the model: not in the spec.
    std::map<std::string, double> device_options;
    StrokeParams stroke;                ///< the scripted stroke (tool_radius_m = tool_radius_m)
    /// The workpiece the scripted stroke is planned on ("stroke": {"workpiece": k}, 0..the scene's workpieces - 1).
    std::size_t stroke_workpiece = 0;
    renderer::DisplayConfig display = renderer::DisplayConfig::desktop();  ///< screen, stereo output, eyes, rate
    HeadMode head = HeadMode::kFixed;   ///< head pose provider
    Pose head_pose;                     ///< fixed head / tracker fallback pose (position default: display.default_head_m)
    std::vector<renderer::HeadWaypoint> head_waypoints;  ///< the scripted head (kScripted; may be set for any mode)
    bool head_loop = false;             ///< the scripted head repeats
    double tracker_timeout_s = 0.1;     ///< a tracker pose older than this falls back to head_pose, s
    int dtrack_port = 5000;             ///< kDTrack: UDP port DTrack sends to (1..65535)
    int dtrack_body = 0;                ///< kDTrack: DTrack id of the head body (0..63)
    std::string dtrack_bind = "0.0.0.0";  ///< kDTrack: local IPv4 address to listen on
    bool wand_dtrack = false;           ///< a DTrack Flystick navigates the scene (app/input/wand_navigation.hpp)
    int wand_port = 5000;               ///< wand: UDP port (the head's receiver is shared when it is the same)
    int wand_flystick = 0;              ///< wand: DTrack Flystick id (0..15)
    std::string wand_bind = "0.0.0.0";  ///< wand: local IPv4 address to listen on
    double wand_timeout_s = 0.1;        ///< wand: a Flystick sample older than this stops navigation, s
    /// The scene's "bindings" object as JSON text ("" = none), checked by the session against its devices
    /// (app/actions/bindings.hpp apply_bindings).
    std::string bindings;
    RunStudy study;                     ///< a study scene's objects instead of a workpiece (study.enabled)
    /// Spheres beside the workpiece ("objects"): felt through their undeformed surfaces (spec.elastic_objects) and
    /// drawn, the elastic ones dented within their radius of influence while the tool presses them.
    std::vector<SceneSphere> objects;
    /// The flystick / tracked-body drivers: the DTrack target that is the tool ("device": {"driver": "flystick",
    /// "port": 5000, "id": 0, "bind_address": "0.0.0.0", "timeout_s": 0.1}; devices/tracking/tracked_tool_device.hpp).
    int tracked_port = 5000;                 ///< UDP port (the head's or the wand's receiver is shared on the same port)
    int tracked_id = 0;                      ///< DTrack Flystick id (0..15) or body id (0..63)
    std::string tracked_bind = "0.0.0.0";    ///< local IPv4 address to listen on
    double tracked_timeout_s = 0.1;          ///< a sample older than this disengages the tool, s
};

/// Reads a scene from parsed JSON (form on RunScene). `source` names the file in messages; relative mesh
/// paths are resolved against `base_dir`. Throws tridex::Error "<source>: field '<a.b>': <what is wrong>" for
/// a wrong type, an out-of-range or non-finite value, an unknown name, an unknown field, or a mesh file that
/// does not exist; display errors come from display_config_from_json with source "<source>: field 'display'".
RunScene run_scene_from_json(const nlohmann::json& json, const std::string& source, const std::string& base_dir);

/// Loads a scene file (JSON); an empty path loads default_scene_path(). Throws tridex::Error naming the file
/// when it cannot be read or is not valid JSON, and as run_scene_from_json for bad fields.
RunScene load_run_scene(const std::string& path);

/// The bundled default scene (assets/default_scene.json): found through $TRIDEX_ASSETS, then ./assets, then
/// the source tree's assets folder. Throws tridex::Error when it is missing.
std::string default_scene_path();

}  // namespace tridex::app
