// compute/mesh/mesh_obj_mtl.hpp - a triangle mesh as Wavefront OBJ with a material library (.mtl): one named material
// per palette entry the mesh uses, its triangles grouped under it. OpenMesh's OBJ writer names the materials it makes
// from face colours itself ("Material0", ...), so this small writer keeps the palette's names.
#pragma once

#include <array>
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

/// A material of an OBJ file's library: its name (1..kMaterialNameMax of [A-Za-z0-9_-], unique in the file) and its
/// colour as the renderer shows it (sRGB-encoded, each in [0, 1]), written as Kd.
struct ObjMaterial {
    std::string name;
    std::array<float, 3> rgb{};
};

/// One object of an OBJ file: its name (an `o` line, which Blender and most tools import as an object of its own;
/// "" = no `o` line), its mesh (positions in the caller's unit, triangles CCW from outside) and, per triangle, the
/// index of its material in the file's materials.
struct ObjObject {
    std::string name;
    const TriMesh* mesh = nullptr;
    std::vector<std::uint16_t> triangle_materials;
};

/// Writes several objects to one OBJ file with one material library beside it (mtl_path_for): the library holds
/// the materials some triangle uses, in index order; the OBJ names it (mtllib), then per object its `o` line, its
/// vertices and, per material it uses in index order, `usemtl NAME` and its triangles (1-based indices over the whole
/// file). Both files are written atomically, the library first. Throws tridex::Error "<path>: ..." for no triangles
/// at all, a missing mesh, a triangle count or index that does not match, a material index past `materials`, a bad
/// or repeated material name or an object name with white space, or a failed write.
void write_obj_objects(const std::string& obj_path, std::span<const ObjObject> objects,
                       std::span<const ObjMaterial> materials);

}  // namespace tridex::compute
