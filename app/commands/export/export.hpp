// app/commands/export/export.hpp - `tridex export MODEL.tdx OUT.{stl,obj,ply}`: a saved model as one closed mesh for other tools.
#pragma once

#include <cstddef>
#include <string>

namespace tridex::app {

/// Options of `tridex export`.
struct ExportOptions {
    std::string model;         ///< the saved model (.tdx)
    std::string out;           ///< the mesh file; its extension picks the format (.stl binary, .obj, .ply binary)
    std::string units = "m";   ///< "m" (world metres), "mm" (world millimetres, what CAM and printers expect) or "in"
    /// "world": the session's coordinates (the workpiece placed and scaled in front of the screen), in `units`;
    /// "input": the input mesh's own frame and units (the model's to_world undone), so the export lines up with the
    /// mesh it was carved from in another tool. `units` must then stay "m" (the mesh's units are its own).
    std::string frame = "world";
};

/// What an export wrote.
struct ExportResult {
    std::size_t vertices = 0, triangles = 0;
    std::size_t boundary_edges = 0;  ///< 0: the mesh is closed
    double volume_dexel_m3 = 0.0;    ///< the model's tri-dexel volume (compute::dexel_volume_m3), m^3
    double volume_mesh_m3 = 0.0;     ///< the exported mesh's enclosed volume, m^3 (whatever the units written)
};

/// Loads the model, contours all of it on the CPU (compute::Contourer, as a session's final mesh), scales it to
/// `units` (or maps it back into the input mesh's frame) and writes it atomically (compute::write_mesh_file); PLY
/// vertices carry the model palette's colour of their material (8-bit sRGB), and an OBJ comes with a material library
/// beside it (compute::write_obj_with_materials: one material per palette entry used, named by the palette). Prints one summary line. Throws tridex::Error with one line for a bad model file, an
/// unknown format or unit, an output that cannot be written.
ExportResult run_export(const ExportOptions& options);

}  // namespace tridex::app
