// app/scene/workpiece_source.hpp - where a session's workpiece comes from: a closed mesh scan-converted at a resolution,
// or a saved model (.tdx) restored exactly; and the checks that let a replay trust the same source again.
#pragma once

#include <string>
#include <vector>

#include "app/scene/session_spec.hpp"
#include "compute/model/tridexel.hpp"
#include "core/math.hpp"

namespace tridex::app {

/// The placed, scan-converted workpiece.
struct Workpiece {
    std::string mesh_path;          ///< the file it came from
    int resolution = 0;             ///< lattice cells along the longest side
    Mat4 to_world{1.0};             ///< input mesh units -> world metres (uniform scale + translation)
    double volume_mesh_m3 = 0.0;    ///< exact volume of the transformed input mesh
    double volume_dexel_m3 = 0.0;   ///< tri-dexel volume right after scan conversion
    double scan_s = 0.0;            ///< scan-conversion wall time, s
    compute::TriDexel model;        ///< the tri-dexel solid (carved in place by the session)
    /// The materials' names and colours: a saved model's (compute::TdxModel::palette), else the default.
    MaterialPalette palette = default_material_palette();
};

/// Loads `mesh_path` (closed mesh), scales it so its longest side is stock_m and centres it on centre_m
/// (world m), and scan-converts it at `resolution` cells along the longest side. Throws tridex::Error on a
/// bad file, an impossible resolution, or a model that would not fit in memory.
Workpiece prepare_workpiece(const std::string& mesh_path, int resolution, double stock_m, const Vec3& centre_m);

/// The workpiece of a saved model file (compute/model/tdx_file.hpp): the model bit for bit as saved (dirty
/// flags set on every tile, so the first contour covers it all), its transform; mesh_path is the model file,
/// resolution its longest lattice side (cells), volume_mesh_m3 = volume_dexel_m3 = its tri-dexel volume (the model
/// is its own reference), scan_s the load time (s). The model may take at most model_memory_budget_bytes().
/// Throws tridex::Error "<path>: ..." for a missing, damaged or too large file.
Workpiece workpiece_from_model(const std::string& tdx_path);

/// The session's workpiece for `spec`, and the spec completed: with spec.model_path, the saved model
/// (workpiece_from_model), and resolution, stock_m (the longest side less the 2-cell margins, m) and
/// workpiece_centre_m (the lattice's centre, model m) taken from it, model_crc32/model_bytes set, and its palette when
/// spec.palette is the default (a scene that names materials keeps its own), and a scene's workpiece_position_m turned
/// into workpiece_shift_m from that centre; else the mesh
/// scan-converted (prepare_workpiece) with mesh_crc32/mesh_bytes set. SIGINT or SIGTERM meanwhile ends the program
/// at once (StopEndsSetUp): there is nothing to keep yet. Throws tridex::Error as those do.
Workpiece prepare_session_workpiece(SessionSpec& spec);

/// The session's further workpieces (s.more_workpieces, in order), each prepared as prepare_session_workpiece prepares
/// the first (a saved model loaded, else the mesh scan-converted), and each entry of s.more_workpieces completed as
/// that function completes the first (CRC-32s and sizes, a model's lattice and centre, a placed model's shift). Throws
/// tridex::Error "workpieces[k]: ..." as prepare_session_workpiece does.
std::vector<Workpiece> prepare_more_workpieces(SessionSpec& s);

/// Writes the session's model after stop() (the CPU model, which mirrors the GPU's) with its transform and
/// spec_to_json(spec) as the settings and spec.palette to `path` (.tdx, atomically: a failed save leaves an existing file as it
/// was). Throws tridex::Error "<path>: ..." when it cannot be written.
void save_session_model(const std::string& path, const Workpiece& workpiece, const SessionSpec& spec);

/// Refuses the files a recorded spec names when they are no longer the bytes the session used: each workpiece's mesh
/// or saved model, a mesh tool's mesh and each reference object's mesh, each against its recorded CRC-32 and size (a
/// file recorded without them, size 0, is accepted). `since` names the record ("the recording", "the session").
/// Throws tridex::Error "<source>: the <workpiece mesh|workpiece model|tool mesh|reference mesh> <path> changed since
/// <since> (CRC-32 0x..., recorded 0x...); it would carve a different model" ("it would feel different" for a
/// reference), or "... cannot be read" for a missing file.
void check_inputs_unchanged(const SessionSpec& spec, const std::string& source, const std::string& since);

}  // namespace tridex::app
