// compute/mesh/mesh_export.hpp - writing a TriMesh to disk.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// Writes the mesh as binary little-endian PLY (own small writer): element vertex with float x, y, z in
/// metres, element face with `list uchar int vertex_indices` (CCW from outside). Positions are rounded
/// to 32-bit floats (about 1e-7 relative). Throws tridex::Error "<path>: ..." when the file cannot be
/// opened or written, or when a triangle references a vertex index >= positions.size() or the mesh has
/// more than 2^31 - 1 vertices (PLY int indices). When `materials` is not empty it holds one material id
/// per vertex (e.g. Contourer::mesh_materials()) and each vertex also gets `property uchar material`
/// (after z); a size other than 0 or positions.size() throws tridex::Error (nothing written).
void write_ply(const std::string& path, const TriMesh& mesh, std::span<const std::uint8_t> materials = {});

}  // namespace tridex::compute
