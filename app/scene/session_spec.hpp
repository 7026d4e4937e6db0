// app/scene/session_spec.hpp - everything that decides a session's result, one type for every session: the
// demo's flags and a scene file fill it, a recording carries it, and a replay rebuilds the same session.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/scene/reference_objects.hpp"
#include "app/scene/workpiece_spec.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "core/material_palette.hpp"
#include "core/math.hpp"
#include "core/symmetry.hpp"
#include "core/tool_shape.hpp"
#include "core/tri_mesh.hpp"
#include "devices/haptic_device.hpp"
#include "devices/registry/device_registry.hpp"
#include "haptics/haptic_loop.hpp"
#include "haptics/materials.hpp"

namespace tridex::app {

/// One entry of a session's materials table: the contact parameters of a material id.
struct MaterialEntry {
    int id = 0;              ///< material id 0..255 (0 = the workpiece's own material; 1..7 the palette)
    haptics::Material material;
};

/// The range of a session's workspace scale (device -> world gain). At the lowest, an Omni's 16 cm reach moves the tool
/// 1.6 mm, little more than the smallest tool's diameter; a smaller gain divides every world distance of the hand's
/// path into device metres beyond any device's reach (and, near 0, beyond a double's).
inline constexpr double kWorkspaceScaleMin = 0.01;
inline constexpr double kWorkspaceScaleMax = 100.0;  ///< the other end: an Omni's reach spans 16 m of the world

/// Workpiece, tool, device and haptics settings of one session (SI units). The same spec always gives the
/// same haptic loop configuration (loop_config) and, with the same device samples, the same model.
struct SessionSpec {
    std::string mesh_path;                   ///< workpiece file (absolute when recorded)
    /// CRC-32 (IEEE) and size of the workpiece file's bytes, so a replay refuses a mesh that changed; 0 = not known
    /// (recordings made before it was stored).
    std::uint32_t mesh_crc32 = 0;
    std::uint64_t mesh_bytes = 0;
    /// A saved model (.tdx, compute/model/tdx_file.hpp) the session starts from instead of the mesh (absolute when
    /// recorded); empty = scan-convert mesh_path. With a model, resolution, stock_m and workpiece_centre_m are the
    /// model's (set by prepare_session_workpiece) and mesh_path is unused.
    std::string model_path;
    /// CRC-32 (IEEE) and size of the model file, so a replay refuses a model that changed; 0 = not known.
    std::uint32_t model_crc32 = 0;
    std::uint64_t model_bytes = 0;
    /// A training-study model ("haptic_training" | "visual_training" | "test") whose felt walls
    /// (app/scene/study_walls.hpp) are the workpiece, built from the study scene file mesh_path (absolute when
    /// recorded, its CRC-32 in mesh_crc32); "" = a mesh or saved-model workpiece.
    std::string study_model;
    int resolution = 256;                    ///< lattice cells along the longest side
    double stock_m = 0.3;                    ///< longest side of the placed workpiece, m
    Vec3 workpiece_centre_m{0.0, 0.0, 0.3};  ///< where the workpiece's lattice is centred, in its model frame, m
    /// The workpiece's pose (workpiece_pose()): turned by workpiece_turn (model -> world, unit quaternion) about its
    /// centre, then moved by workpiece_shift_m (world m). Identity and zero (the default): the model frame is the
    /// world, as in every session before workpieces were posed. The lattice never turns: the pose moves the solid.
    Quat workpiece_turn{1.0, 0.0, 0.0, 0.0};
    Vec3 workpiece_shift_m{0.0};
    /// A saved model's centre as the scene placed it (workpiece.position_m, world m), until
    /// prepare_session_workpiece turns it into workpiece_shift_m (the model's own centre is known only once it is
    /// loaded); empty = where it was saved. Not part of the settings: workpiece_shift_m is.
    std::optional<Vec3> workpiece_position_m{};
    /// The session's workpieces after this first one (a scene's "workpieces"[1..], app/scene/workpiece_list.hpp):
    /// each its own model, lattice and pose, sculpted beside the first by the same tool. At most
    /// haptics::kMaxLoopWorkpieces - 1; empty (the default) = one workpiece, as in every session before.
    std::vector<WorkpieceSpec> more_workpieces{};
    /// The tool that cuts and touches (core/tool_shape.hpp). kMesh: radius_m is the placed mesh's bounding
    /// radius about its tip (set_tool_mesh), mesh_id 0 (the session's one mesh tool).
    ToolShape tool{ToolKind::kBall, 0.008, 0.0, 0};
    /// kMesh: the tool's closed mesh file (absolute when recorded), placed by app/scene/tool_mesh.hpp load_tool_mesh
    /// (tip at the tool origin, +y the axis) with the longest side of its bounding box tool_size_m (m); the
    /// CRC-32 (IEEE) and size of the file's bytes, so a replay refuses a tool mesh that changed (0 = not known).
    std::string tool_mesh_path;
    double tool_size_m = 0.0;
    std::uint32_t tool_mesh_crc32 = 0;
    std::uint64_t tool_mesh_bytes = 0;
    /// Contact points over the tool (haptics::tool_points_for): ball 1 = its centre god-object, 3..64 an
    /// interaction mesh; flat_end 1 = 32 points over it, 2 = the wand's two ends, 8..64 points over it; mesh
    /// 1 = 32 points over its surface, 8..64 that many.
    int points = 1;
    std::string device_driver = "simulated"; ///< device driver by registry name (simulated; replay when replaying)
    std::string device = "omni";             ///< device profile: omni | wand | 6dof | falcon
    /// falcon: the firmware file from the user's own installation (--falcon-firmware, a scene's device.firmware).
    /// Where the firmware comes from does not decide the result, so it is not part of the spec's JSON.
    std::string device_firmware;
    /// net: the device server's "HOST:PORT" (not part of the spec's JSON: where a device is served does not decide the
    /// result). Other drivers: the unit ("" = the first found).
    std::string device_serial;
    /// Drivers whose link can be sealed (net): the key file, or the name of the environment variable holding the
    /// passphrase (devices::DeviceInputs::key_file); both "" = not authenticated. Not part of the spec's JSON: a key
    /// does not decide the result, and must not travel in a journal or recording.
    std::string device_key_file;
    std::string device_passphrase_env;  ///< see device_key_file
    /// net: where the contact loop runs, "distributed" or "local" (devices/net/net_device.hpp).
    std::string haptic_rendering = "distributed";
    std::string workspace_mode = "peng_moving";  ///< peng_moving | scaling | clutching | bubble (Peng et al. 4.1 and peers)
    double workspace_scale = 1.0;            ///< device -> world gain, [kWorkspaceScaleMin, kWorkspaceScaleMax]
    /// World position of the device frame's origin, m (the loop's device_to_world.position). Sessions put
    /// the device's home (devices::home_position_m, its workspace centre) on the stroke's centre, so this is
    /// centre - workspace_scale * home; = the workspace centre for a device whose workspace is centred.
    Vec3 device_origin_m{0.0};
    double stiffness_n_per_m = 700.0;        ///< contact stiffness kp, N/m (0.7 N/mm, Omni-class)
    double damping_n_s_per_m = 0.5;          ///< contact damping kd, N*s/m
    double static_friction = 0.2;            ///< Coulomb static coefficient on the proxy
    double dynamic_friction = 0.15;          ///< Coulomb dynamic coefficient (<= static)
    bool cutting = true;                     ///< reaction force against the tool's advance while carving
    double period_s = 1e-3;                  ///< haptic loop period, s
    std::string op = "subtract";             ///< what the tool does: subtract | union | paint | push | smooth
    int material = 1;                        ///< material id union adds and paint sets (1..7, the palette); cuts expose 0
    /// Sculpting symmetry the session starts with (core/symmetry.hpp spelling: "off", "x", "xz", "radial:6:z"; a
    /// scene's "symmetry", `--symmetry`); the samples carry it, so the journal and a replay apply the same copies.
    std::string symmetry = "off";
    /// Per-material contact parameters (ids not listed use stiffness, damping and friction above); empty =
    /// one material everywhere.
    std::vector<MaterialEntry> materials;
    /// The materials' names and colours (core/material_palette.hpp): what the renderer draws, the menu and keys offer
    /// and export writes. It does not change the model, but a recording, a journal and a saved model carry it so
    /// that what replays looks as it did; those without one read as default_material_palette().
    MaterialPalette palette = default_material_palette();
    /// Elastic (and rigid) spheres felt beside the workpiece (haptics::HapticLoopConfig::elastic_objects; a scene's
    /// "objects"); empty = none.
    std::vector<haptics::ElasticSphere> elastic_objects;
    /// Reference objects: closed meshes placed beside the workpiece, drawn and felt, never sculpted (a scene's
    /// "references"; app/scene/reference_objects.hpp). The felt ones change the hand's path, so a recording carries
    /// them; empty = none.
    std::vector<ReferenceSpec> references;
    /// Memory the undo history may keep, bytes (compute::UndoHistory; oldest strokes dropped first). It does not
    /// change the model, but a journal replays its undos with it.
    std::size_t history_budget_bytes = std::size_t{256} << 20;
    /// Keep the specks a cut leaves floating (--keep-islands). false: when a stroke that cut closes, the pieces it
    /// left wholly inside its swept box (grown by its tool's radius) that are smaller than its tool's ball are removed
    /// (compute::find_islands), as part of the stroke (undone with it). It changes the model, so a recording and a
    /// journal carry it; those made before it existed read as true (their sessions kept every piece).
    bool keep_islands = false;
    /// Set a CPU aside for the haptic loop's thread once SCHED_FIFO is granted (haptics::HapticLoopConfig::
    /// reserve_cpu); false (--shared-haptic-cpu) lets it share its CPU with the drawing thread. Not part of the
    /// model: recordings and journals do not carry it.
    bool reserve_haptic_cpu = true;
    /// The most push or smooth sweeps the sculpt thread applies as one group (compute::apply_clay_batch's
    /// group_sweeps, 1..compute::kClayGroupSweepsMax). The grouping decides the model, so a recording and a journal
    /// carry it; those made before it existed read as 16 (the size their sessions grouped by).
    std::size_t clay_group_sweeps = compute::kClayGroupSweeps;
};

/// The journal replay settings of a session (compute::journal_apply): its undo budget, speck removal and clay
/// group size, so that a replay builds the model the session built.
compute::JournalApplyFrom replay_settings(const SessionSpec& s);

/// The ToolOp named by `name` (subtract, union, paint, push, smooth, pull, or none: the tool touches but never changes
/// the model); throws tridex::Error listing the names.
ToolOp parse_tool_op(const std::string& name);

/// The device profile named by `name` (omni, wand, 6dof); throws tridex::Error listing the names.
devices::DeviceProfile device_profile(const std::string& name);

/// The session's device, made by the device registry (devices::builtin_registry) from device_driver and the
/// profile `device`, with `inputs` (the loop period; the simulated hand's path or the replayed samples). The
/// device is closed: SessionRuntime opens and homes it. Throws tridex::Error naming device.driver or
/// device.profile when the registry refuses them.
std::unique_ptr<devices::HapticDevice> make_device(const SessionSpec& s, const devices::DeviceInputs& inputs);

/// A net device in local haptic rendering gets the loop's contact parameters and workspace mapping (the device
/// server's god-object loop renders with them); any other device is left alone. Call before the loop starts.
void configure_net_device(devices::HapticDevice& device, const haptics::HapticLoopConfig& cfg);

/// The haptic loop configuration for this spec, with `max_ticks` records preallocated: contact from the
/// stiffness, damping and friction (and the materials table when given), the tool and its contact points
/// (haptics::tool_points_for; the interaction-mesh mode for more than two points), op and material. The
/// same spec always gives the same configuration. Throws tridex::Error naming the field on an impossible
/// value (points for the tool, friction order, unknown workspace mode, unknown op, material outside 1..7, a
/// materials entry out of range).
/// A kMesh tool's contact points come from `tool_mesh_m` (its mesh in the tool frame, m; SessionRuntime passes
/// the one it sweeps) or, when null, from tool_mesh_path loaded again; cfg.tool.radius_m is then that mesh's
/// bounding radius. The reference objects are not loaded here (their distance fields take a while to build):
/// SessionRuntime adds them (prepare_references) to the configuration it runs.
haptics::HapticLoopConfig loop_config(const SessionSpec& s, std::size_t max_ticks, const TriMesh* tool_mesh_m = nullptr);

/// The workpiece's model frame -> the world (m): turned by s.workpiece_turn about s.workpiece_centre_m, then moved by
/// s.workpiece_shift_m; identity for an unposed workpiece. loop_config() puts it in HapticLoopConfig::workpiece_pose,
/// and the views draw and pick the workpiece through it. Needs a unit workpiece_turn (validate_spec checks it).
Pose workpiece_pose(const SessionSpec& s);

/// The button bits that engage the tool for a device driver, from its capabilities (DriverCapabilities::
/// engage_button: the desk mouse's left button, a Flystick's trigger); 0 (always engaged) for drivers without one.
/// Throws tridex::Error "device.driver: unknown driver ..." for a driver the registry does not have.
std::uint32_t engage_mask_for(const std::string& driver);

/// The registered capabilities of `driver` (devices::builtin_registry); throws tridex::Error "device.driver:
/// unknown driver ..." for a name the registry does not have.
const devices::DriverCapabilities& driver_caps(const std::string& driver);

/// Makes `s` use the closed mesh tool in `path` scaled to `size_m` (m): kind kMesh, the absolute path, the size,
/// radius_m = the placed mesh's bounding radius, mesh_id 0, and the file's CRC-32 and byte count. `what` names
/// the setting in messages ("<scene>: field 'tool.mesh'", "--tool-mesh"). Throws tridex::Error "<what>: <path>:
/// ..." for a file that cannot be read or is not a closed mesh (app/scene/tool_mesh.hpp).
void set_tool_mesh(SessionSpec& s, const std::string& path, double size_m, const std::string& what);

/// Checks every field against the ranges a session accepts (what the demo's flags and a scene allow), so that a
/// spec read from a file (a recording) is as trustworthy as one typed: resolution 8..4096, stock (1 mm..100 m],
/// finite centres within 1 km, the tool's radius 0.5 mm..a quarter of the stock and a flat end's length 0.5 mm..the
/// stock, a mesh tool's size 1 mm..a quarter of the stock and a readable closed mesh whose bounding radius is
/// tool.radius_m, points 1..64, a known device and profile, workspace scale (0, 100], stiffness (0, 1e5] N/m, damping
/// [0, 1e3] N*s/m, friction 0 <= dynamic <= static <= 10, period [1e-4, 1e-2] s, op and material, the clay group
/// size 1..compute::kClayGroupSweepsMax. Throws
/// tridex::Error "<source>: settings field '<name>': <rule>, got <value>".
void validate_spec(const SessionSpec& s, const std::string& source);

/// CRC-32 (IEEE) and byte count of a file; throws tridex::Error "<path>: cannot read" when it cannot.
std::pair<std::uint32_t, std::uint64_t> file_crc32(const std::string& path);

/// The spec as one line of JSON (for a recording's header notes). A palette other than the default is written as
/// "palette": [{"id": 0, "name": "clay", "rgb": [0.8, 0.62, 0.45]}, ...] (all entries, floats exact); the
/// default palette is left out, so a default session's JSON is what it was before palettes.
std::string spec_to_json(const SessionSpec& s);

/// Session settings JSON (spec_to_json's) with their "resolution" set to `resolution`: a model saved after its
/// coarseness changed, or re-sampled by `tridex resample`. The text as it was when it is not a JSON object holding a
/// "resolution" (the settings are opaque to the model file).
std::string settings_at_resolution(const std::string& settings_json, int resolution);

/// Parses spec_to_json's output (and that of older recordings: a ball tool from tool_radius_m, no
/// materials, the default palette, keep_islands true and clay_group_sweeps 16 when absent); throws tridex::Error "<source>: settings field '<name>': ..." on a
/// missing or ill-typed field.
SessionSpec spec_from_json(const std::string& text, const std::string& source);

}  // namespace tridex::app
