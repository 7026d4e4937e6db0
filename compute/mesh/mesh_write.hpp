// compute/mesh/mesh_write.hpp - writing a closed triangle mesh as STL, OBJ or PLY through OpenMesh, atomically.
// (mesh_export.hpp's write_ply is the sessions' own PLY with material ids; this is for exchange with other tools.)
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// File formats write_mesh_file knows, chosen by the file's extension.
enum class MeshFileFormat {
    kStl,  ///< binary STL (triangles with facet normals; 32-bit floats), the usual input of CAM and 3D printing
    kObj,  ///< Wavefront OBJ text (positions with 9 significant digits, triangles)
    kPly,  ///< binary little-endian PLY (float positions, triangles, optional 8-bit RGB per vertex)
};

/// The format for `path` from its extension (.stl, .obj, .ply; any case). Throws tridex::Error
/// "<path>: unknown mesh format '.ext'; use .stl, .obj or .ply".
MeshFileFormat mesh_file_format(const std::string& path);

/// Writes `mesh` (positions in whatever unit the caller chose; triangles CCW from outside) to `path` in the format
/// of its extension through OpenMesh, first to "<path>.tmp-<pid>", then fsync'ed and renamed over `path`, so a
/// failed export leaves an existing file as it was. `colours`: empty, or one sRGB colour per vertex (PLY only;
/// STL and OBJ ignore them). Throws tridex::Error "<path>: ..." when the mesh is empty, a triangle indexes past
/// the vertices, OpenMesh refuses a face (a non-manifold mesh), colours have the wrong count, or a write fails.
void write_mesh_file(const std::string& path, const TriMesh& mesh,
                     std::span<const std::array<std::uint8_t, 3>> colours = {});

}  // namespace tridex::compute
