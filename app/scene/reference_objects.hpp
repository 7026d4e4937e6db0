// app/scene/reference_objects.hpp - a scene's reference objects: closed meshes placed beside the workpiece, drawn
// and felt, never sculpted; read from the scene, kept in a recording's settings, loaded for a session.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <nlohmann/json_fwd.hpp>

#include "core/math.hpp"
#include "core/tri_mesh.hpp"
#include "haptics/reference_object.hpp"

namespace tridex::renderer {
struct SceneObject;
}

namespace tridex::app {

/// Most reference objects a scene may hold (haptics::kMaxReferenceObjects).
inline constexpr std::size_t kMaxSceneReferences = 8;

/// One reference object of a session (SI units, world frame of DESIGN.md): which mesh, how large, where and how
/// turned, how stiff it feels and its colour.
struct ReferenceSpec {
    std::string name;                   ///< for messages and the report
    std::string mesh_path;              ///< closed mesh file (absolute once read from a scene)
    std::uint32_t mesh_crc32 = 0;       ///< CRC-32 (IEEE) of the file, so a replay refuses a mesh that changed
    std::uint64_t mesh_bytes = 0;       ///< size of the file, bytes
    double size_m = 0.1;                ///< longest side of its bounding box once placed, m, (0, 10]
    Vec3 position_m{0.0};               ///< where the centre of its bounding box stands, world m
    Quat orientation{1.0, 0.0, 0.0, 0.0};  ///< its turn about that centre (unit quaternion)
    double stiffness_n_per_m = 700.0;   ///< penalty stiffness, N/m, (0, 1e5]
    /// Spacing of its distance field, m; 0 = size_m / kReferenceGridCells, at least kReferenceMinCellM.
    double grid_cell_m = 0.0;
    Vec3 colour{0.62, 0.64, 0.68};      ///< linear RGB, each in [0, 1]
    double alpha = 1.0;                 ///< opacity, [0, 1]
};

/// Cells of a reference's distance field along its longest side by default (ReferenceSpec::grid_cell_m = 0).
inline constexpr double kReferenceGridCells = 96.0;

/// The finest default spacing of a reference's distance field, m: finer than a haptic device resolves.
inline constexpr double kReferenceMinCellM = 0.0005;

/// How far beyond its mesh a reference's distance field reaches, m: contacts are looked for within it.
inline constexpr double kReferenceMarginM = 0.02;

/// Reads a scene's "references" array (each entry {"name", "mesh" (relative to base_dir), "size_m", "position_m",
/// "axis", "angle_deg", "stiffness_n_per_m", "grid_cell_m", "colour": [r, g, b(, a)]}), 1 to kMaxSceneReferences
/// entries; the mesh file must exist (its CRC-32 is taken). Throws tridex::Error "<source>: field
/// 'references[i].<name>': <what is wrong>" for a wrong type, an out-of-range value, a zero axis, a missing file or an
/// unknown field.
std::vector<ReferenceSpec> references_from_scene_json(const nlohmann::json& references, const std::string& source,
                                                      const std::string& base_dir);

/// A reference as a recording's settings keep it (every field of ReferenceSpec; the orientation as "orientation_wxyz").
nlohmann::json reference_settings_json(const ReferenceSpec& r);

/// Reads reference_settings_json's form; `what` names the entry in messages ("<file>: settings field
/// 'references[i]'"). Throws tridex::Error "<what>.<field>: ..." for a missing or bad field.
ReferenceSpec reference_from_settings_json(const nlohmann::json& j, const std::string& what);

/// A reference made ready for a session: its mesh in its own frame (m, centred on its bounding box, scaled to
/// size_m), what the haptic loop feels, and how long its distance field took to build.
struct PreparedReference {
    TriMesh mesh_m;                    ///< own frame, m
    haptics::ReferenceObject object;   ///< distance field, pose, stiffness
    double build_s = 0.0;              ///< loading and building its distance field, s (wall time)
};

/// A reference's mesh in its own frame, m: loaded (compute::load_closed_mesh: closed, manifold, oriented), centred on
/// its bounding box and scaled so that the box's longest side is size_m (compute::fit_to_stock). Throws tridex::Error
/// "<path>: <reason>" as the loader does, or for a mesh without extent.
TriMesh load_reference_mesh(const ReferenceSpec& r);

/// Loads each reference's mesh (compute::load_closed_mesh: closed, manifold, oriented), places it and builds its
/// distance field (compute::build_distance_grid, margin kReferenceMarginM, at most 256 MB each). Throws tridex::Error
/// "reference '<name>': <path>: <reason>" as the loader does, or for a grid that does not fit.
std::vector<PreparedReference> prepare_references(const std::vector<ReferenceSpec>& refs);

/// report.json `references`: per object {name, mesh, triangles, size_m, position_m, grid: {nodes, cell_m, bytes},
/// build_s}; `prepared` in the order of `refs`.
nlohmann::json references_report_json(const std::vector<ReferenceSpec>& refs,
                                      const std::vector<PreparedReference>& prepared);

/// The transform a reference's own-frame mesh is drawn with: its pose (rotation then translation).
glm::mat4 world_from_reference(const ReferenceSpec& r);

/// How the renderer draws reference `r` whose own-frame mesh is `mesh_m` (kept by address: it must outlive the
/// object): in its colour, placed by world_from_reference.
renderer::SceneObject reference_scene_object(const ReferenceSpec& r, const TriMesh& mesh_m);

}  // namespace tridex::app
