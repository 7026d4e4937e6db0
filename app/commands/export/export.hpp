// app/commands/export/export.hpp - `tridex export MODEL.tdx|SCENE.json OUT.{stl,obj,ply}`: a saved model, or the
// workpiece of a scene where the scene places it (with its reference objects if asked), as closed meshes for other
// tools.
#pragma once

#include <cstddef>
#include <string>

namespace tridex::app {

/// Options of `tridex export`.
struct ExportOptions {
    /// The saved model (.tdx), or a scene file (.json; e.g. the FILE.scene.json a posed session saves beside its
    /// model): its workpiece (a saved model, or a mesh scan-converted as a session would) placed by its pose.
    std::string model;
    std::string out;           ///< the mesh file; its extension picks the format (.stl binary, .obj, .ply binary)
    std::string units = "m";   ///< "m" (world metres), "mm" (world millimetres, what CAM and printers expect) or "in"
    /// "world": the session's coordinates (the workpiece placed and scaled in front of the screen), in `units`;
    /// "input": the input mesh's own frame and units (the model's to_world undone), so the export lines up with the
    /// mesh it was carved from in another tool. `units` must then stay "m" (the mesh's units are its own).
    std::string frame = "world";
    /// "workpiece": the workpiece alone (a scene of several: the first in `out`, each further one k in its own file,
    /// path_for_workpiece(out, k): "carved-wp2.stl"); "all": a scene's workpieces and its reference objects in one file
    /// (an OBJ object each, "workpiece", "workpiece_2", ..., one material per reference named "ref_<name>"; STL and
    /// PLY one mesh, PLY in each one's colour). "all" needs a scene and the world frame.
    std::string objects = "workpiece";
};

/// What an export wrote.
struct ExportResult {
    std::size_t vertices = 0, triangles = 0;
    std::size_t boundary_edges = 0;  ///< 0: the mesh is closed
    double volume_dexel_m3 = 0.0;    ///< the model's tri-dexel volume (compute::dexel_volume_m3), m^3
    double volume_mesh_m3 = 0.0;     ///< the exported workpiece mesh's enclosed volume, m^3 (whatever the units written)
    std::size_t references = 0;      ///< reference objects written beside the workpiece (ExportOptions::objects "all")
    std::size_t workpieces = 1;      ///< workpieces written (a scene of several: each to its own file, or all in one)
};

/// Loads the model (from a scene: prepare_session_workpiece, placed by workpiece_pose), contours all of it on the CPU
/// (compute::Contourer, as a session's final mesh), places it in the world by the scene's pose and scales it to
/// `units` (or maps it back into the input mesh's frame, where the pose plays no part), adds the scene's reference
/// objects (objects "all": each mesh placed by its pose, as the session draws it), a scene's further workpieces each
/// likewise (each to its own file beside `out`, or with "all" in the one file), and writes it atomically
/// (compute::write_mesh_file, or compute::write_obj_objects for an OBJ); PLY vertices carry the model palette's colour of their material (8-bit sRGB), and an OBJ comes with a material library
/// beside it (one material per palette entry used, named by the palette).
/// Prints one summary line. Throws tridex::Error with one line for a bad model or scene file (a study scene has no
/// workpiece), an unknown format, unit or objects choice, "all" with a model file or the input frame, an output that
/// cannot be written.
ExportResult run_export(const ExportOptions& options);

}  // namespace tridex::app
