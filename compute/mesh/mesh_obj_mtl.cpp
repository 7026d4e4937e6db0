// compute/mesh/mesh_obj_mtl.cpp - OBJ text with a material library named from the palette.
#include "compute/mesh/mesh_obj_mtl.hpp"

#include <algorithm>
#include <array>
#include <cstdio>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace tridex::compute {

namespace {

std::string file_name(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

void write_text(const std::string& path, const std::string& text) {
    AtomicFile file(path);
    file.write(text.data(), text.size());
    file.commit();
}

std::string mtl_text(const MaterialPalette& palette, const std::array<bool, kPaletteSize>& used) {
    std::string out = "# tridex material library: Kd is the sRGB colour / 255 (as the scene named it and the renderer shows it)\n";
    char line[160];
    for (int m = 0; m < kPaletteSize; ++m) {
        if (!used[m]) continue;
        const PaletteEntry& e = palette.entries[m];
        std::snprintf(line, sizeof line, "\nnewmtl %s\n# material %d, sRGB %s\nKa 0 0 0\nKd %.6f %.6f %.6f\nKs 0 0 0\nd 1\nillum 1\n",
                      e.name.c_str(), m, hex_colour(srgb8(e)).c_str(), static_cast<double>(e.rgb[0]),
                      static_cast<double>(e.rgb[1]), static_cast<double>(e.rgb[2]));
        out += line;
    }
    return out;
}

}  // namespace

std::vector<std::uint8_t> triangle_materials(const TriMesh& mesh, std::span<const std::uint8_t> vertex_materials) {
    const std::size_t nv = mesh.positions.size();
    if (vertex_materials.size() != nv)
        throw Error(std::to_string(vertex_materials.size()) + " vertex materials for " + std::to_string(nv) + " vertices");
    std::vector<std::uint8_t> out;
    out.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
        std::array<std::uint8_t, 3> m{};
        for (int k = 0; k < 3; ++k) {
            if (static_cast<std::size_t>(t[k]) >= nv)
                throw Error("a triangle indexes vertex " + std::to_string(t[k]) + " of " + std::to_string(nv));
            const std::uint8_t id = vertex_materials[static_cast<std::size_t>(t[k])];
            m[k] = id <= kMaxMaterialId ? id : 0;
        }
        std::uint8_t pick = std::min({m[0], m[1], m[2]});
        if (m[0] == m[1] || m[0] == m[2]) pick = m[0];
        else if (m[1] == m[2]) pick = m[1];
        out.push_back(pick);
    }
    return out;
}

std::string mtl_path_for(const std::string& obj_path) {
    const std::size_t slash = obj_path.find_last_of('/'), dot = obj_path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return obj_path + ".mtl";
    return obj_path.substr(0, dot) + ".mtl";
}

void write_obj_with_materials(const std::string& obj_path, const TriMesh& mesh,
                              std::span<const std::uint8_t> vertex_materials, const MaterialPalette& palette) {
    if (mesh.triangles.empty()) throw Error(obj_path + ": the mesh is empty (nothing written)");
    std::vector<std::uint8_t> tri;
    try {
        tri = triangle_materials(mesh, vertex_materials);
    } catch (const Error& e) {
        throw Error(obj_path + ": " + e.what() + " (nothing written)");
    }
    if (const std::string why = palette_problem(palette); !why.empty()) throw Error(obj_path + ": palette: " + why);
    std::array<bool, kPaletteSize> used{};
    for (std::uint8_t m : tri) used[m] = true;
    const std::string mtl = mtl_path_for(obj_path);
    std::string obj = "# tridex export: " + std::to_string(mesh.positions.size()) + " vertices, " +
                      std::to_string(mesh.triangles.size()) + " triangles\nmtllib " + file_name(mtl) + "\n";
    obj.reserve(obj.size() + mesh.positions.size() * 40 + mesh.triangles.size() * 24);
    char line[128];
    for (const Vec3& p : mesh.positions) {
        std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", p.x, p.y, p.z);
        obj += line;
    }
    for (int m = 0; m < kPaletteSize; ++m) {
        if (!used[m]) continue;
        obj += "usemtl " + palette.entries[m].name + "\n";
        for (std::size_t i = 0; i < tri.size(); ++i) {
            if (tri[i] != m) continue;
            const auto& t = mesh.triangles[i];
            std::snprintf(line, sizeof line, "f %lld %lld %lld\n", static_cast<long long>(t[0]) + 1,
                          static_cast<long long>(t[1]) + 1, static_cast<long long>(t[2]) + 1);
            obj += line;
        }
    }
    write_text(mtl, mtl_text(palette, used));
    write_text(obj_path, obj);
}

}  // namespace tridex::compute
