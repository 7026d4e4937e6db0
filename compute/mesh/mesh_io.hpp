// compute/mesh/mesh_io.hpp - loading a closed workpiece mesh from OFF, OBJ, PLY or STL.
#pragma once

#include <string>

#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// Loads a triangle mesh (OFF and PLY, ASCII or binary, with tridex's strict readers read_off and read_ply; OBJ
/// and STL with OpenMesh; by extension, case-insensitive), triangulates polygons (fan), welds exactly coincident vertex positions (a triangle soup such as
/// Wuson.ply becomes closed), drops degenerate triangles, then requires a closed, consistently
/// oriented 2-manifold; flips all triangles when the signed volume is negative. Positions are in the
/// file's own units (scale them with fit_to_stock). OBJ and STL headers and indices are checked first
/// (precheck_mesh_file) so that OpenMesh never sees a file claiming absurd counts; the OFF and PLY readers check
/// every count against the bytes left before they allocate (memory stays a small multiple of the file's size).
/// Throws tridex::Error "<path>: <reason>" for: missing/unreadable file, unknown extension, empty
/// file, header counts impossible for the file size, a malformed header or number (with the line or byte
/// offset), out-of-range or malformed face indices (with the line number or byte offset), no triangles, non-finite coordinates, open mesh ("mesh is not closed:
/// N boundary edges"), non-manifold edges (count), inconsistent orientation (count), zero volume.
/// OpenMesh's own messages (omerr/omlog/omout) are captured, never printed. Thread-safe (serialised).
TriMesh load_closed_mesh(const std::string& path);

/// The second half of load_closed_mesh, for a polygon soup already read from `path` (read_off, read_ply): checks
/// that every position is finite and that there is a triangle, welds, and requires a closed, consistently oriented
/// 2-manifold (flipped outward). Throws tridex::Error "<path>: <reason>" as load_closed_mesh does.
TriMesh closed_mesh_from_soup(const TriMesh& soup, const std::string& path);

}  // namespace tridex::compute
