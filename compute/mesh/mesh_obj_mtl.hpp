// compute/mesh/mesh_obj_mtl.hpp - a triangle mesh as Wavefront OBJ with a material library (.mtl): one named material
// per palette entry the mesh uses, its triangles grouped under it. OpenMesh's OBJ writer names the materials it makes
// from face colours itself ("Material0", ...), so this small writer keeps the palette's names.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/material_palette.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// The material of each triangle of `mesh` from its vertices' materials (one per vertex): the id two or three of its
/// corners share, else the lowest of the three. Ids above kMaxMaterialId read as 0. Throws tridex::Error when
/// `vertex_materials` does not hold one id per vertex or a triangle indexes past the vertices.
std::vector<std::uint8_t> triangle_materials(const TriMesh& mesh, std::span<const std::uint8_t> vertex_materials);

/// The .mtl path beside an .obj path: the extension replaced by ".mtl" ("out/part.obj" -> "out/part.mtl").
std::string mtl_path_for(const std::string& obj_path);

/// Writes `mesh` (positions in the caller's unit, 9 significant digits; triangles CCW from outside) to `obj_path` as
/// OBJ text that names its material library (mtllib, the .mtl beside it, mtl_path_for) and writes that library:
/// one `newmtl NAME` per material the triangles use (triangle_materials), NAME the palette's, with Kd its sRGB colour
/// in [0, 1] (PaletteEntry::rgb, as viewers such as three.js read Kd; a comment gives "#rrggbb"), Ka 0, Ks 0, d 1,
/// illum 1. The OBJ lists every
/// vertex, then per used material in id order `usemtl NAME` and its triangles (1-based). Both files are written
/// atomically (core/atomic_file.hpp), the library first. Throws tridex::Error "<path>: ..." for an empty mesh,
/// bad indices or materials, or a failed write.
void write_obj_with_materials(const std::string& obj_path, const TriMesh& mesh,
                              std::span<const std::uint8_t> vertex_materials, const MaterialPalette& palette);

}  // namespace tridex::compute
