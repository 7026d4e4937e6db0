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

std::string mtl_text(std::span<const ObjMaterial> materials, const std::vector<bool>& used) {
    std::string out = "# tridex material library: Kd is the sRGB colour / 255 (as the scene named it and the renderer shows it)\n";
    char line[160];
    for (std::size_t m = 0; m < materials.size(); ++m) {
        if (!used[m]) continue;
        const ObjMaterial& e = materials[m];
        const PaletteEntry as_entry{e.name, e.rgb};
        std::snprintf(line, sizeof line, "\nnewmtl %s\n# material %zu, sRGB %s\nKa 0 0 0\nKd %.6f %.6f %.6f\nKs 0 0 0\nd 1\nillum 1\n",
                      e.name.c_str(), m, hex_colour(srgb8(as_entry)).c_str(), static_cast<double>(e.rgb[0]),
                      static_cast<double>(e.rgb[1]), static_cast<double>(e.rgb[2]));
        out += line;
    }
    return out;
}

// Why `objects` and `materials` cannot be written ("" when they can); `used` gets which materials a triangle uses.
std::string objects_problem(std::span<const ObjObject> objects, std::span<const ObjMaterial> materials,
                            std::vector<bool>& used) {
    used.assign(materials.size(), false);
    std::size_t triangles = 0;
    for (std::size_t m = 0; m < materials.size(); ++m) {
        if (const std::string why = material_name_problem(materials[m].name); !why.empty())
            return "material " + std::to_string(m) + ": " + why;
        for (std::size_t k = 0; k < m; ++k)
            if (materials[k].name == materials[m].name) return "material name '" + materials[m].name + "' twice";
    }
    for (const ObjObject& o : objects) {
        if (!o.mesh) return "object '" + o.name + "' has no mesh";
        if (o.name.find_first_of(" \t\r\n") != std::string::npos) return "object name '" + o.name + "' has white space";
        if (o.triangle_materials.size() != o.mesh->triangles.size())
            return "object '" + o.name + "': " + std::to_string(o.triangle_materials.size()) + " triangle materials for " +
                   std::to_string(o.mesh->triangles.size()) + " triangles";
        const std::size_t nv = o.mesh->positions.size();
        for (const auto& t : o.mesh->triangles)
            for (int k = 0; k < 3; ++k)
                if (static_cast<std::size_t>(t[k]) >= nv)
                    return "object '" + o.name + "': a triangle indexes vertex " + std::to_string(t[k]) + " of " +
                           std::to_string(nv);
        for (std::uint16_t m : o.triangle_materials) {
            if (m >= materials.size())
                return "object '" + o.name + "': material " + std::to_string(m) + " of " + std::to_string(materials.size());
            used[m] = true;
        }
        triangles += o.mesh->triangles.size();
    }
    if (triangles == 0) return "the mesh is empty";
    return "";
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
    std::vector<ObjMaterial> materials;
    for (const PaletteEntry& e : palette.entries) materials.push_back(ObjMaterial{e.name, e.rgb});
    const ObjObject one{"", &mesh, std::vector<std::uint16_t>(tri.begin(), tri.end())};
    write_obj_objects(obj_path, std::span<const ObjObject>(&one, 1), materials);
}

void write_obj_objects(const std::string& obj_path, std::span<const ObjObject> objects,
                       std::span<const ObjMaterial> materials) {
    std::vector<bool> used;
    if (const std::string why = objects_problem(objects, materials, used); !why.empty())
        throw Error(obj_path + ": " + why + " (nothing written)");
    const std::string mtl = mtl_path_for(obj_path);
    std::size_t vertices = 0, triangles = 0;
    for (const ObjObject& o : objects) {
        vertices += o.mesh->positions.size();
        triangles += o.mesh->triangles.size();
    }
    std::string obj = "# tridex export: " + std::to_string(vertices) + " vertices, " + std::to_string(triangles) +
                      " triangles\nmtllib " + file_name(mtl) + "\n";
    obj.reserve(obj.size() + vertices * 40 + triangles * 24);
    char line[128];
    long long base = 1;  // the first vertex of the object, 1-based over the file
    for (const ObjObject& o : objects) {
        if (!o.name.empty()) obj += "o " + o.name + "\n";
        for (const Vec3& p : o.mesh->positions) {
            std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", p.x, p.y, p.z);
            obj += line;
        }
        for (std::size_t m = 0; m < materials.size(); ++m) {
            if (std::find(o.triangle_materials.begin(), o.triangle_materials.end(), m) == o.triangle_materials.end())
                continue;
            obj += "usemtl " + materials[m].name + "\n";
            for (std::size_t i = 0; i < o.triangle_materials.size(); ++i) {
                if (o.triangle_materials[i] != m) continue;
                const auto& t = o.mesh->triangles[i];
                std::snprintf(line, sizeof line, "f %lld %lld %lld\n", base + t[0], base + t[1], base + t[2]);
                obj += line;
            }
        }
        base += static_cast<long long>(o.mesh->positions.size());
    }
    write_text(mtl, mtl_text(materials, used));
    write_text(obj_path, obj);
}

}  // namespace tridex::compute
