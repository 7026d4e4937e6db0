// compute/mesh/mesh_export.cpp - binary little-endian PLY writer.
#include "compute/mesh/mesh_export.hpp"

#include <bit>
#include <cstdint>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/le_bytes.hpp"

namespace tridex::compute {
namespace {

/// Appends the 4 bytes of v in little-endian order.
void put_u32(std::vector<char>& out, std::uint32_t v) {
    unsigned char b[4];
    tridex::put_u32(b, v);
    out.insert(out.end(), b, b + 4);
}

void put_f32(std::vector<char>& out, float f) { put_u32(out, std::bit_cast<std::uint32_t>(f)); }

}  // namespace

void write_ply(const std::string& path, const TriMesh& mesh, std::span<const std::uint8_t> materials) {
    const std::size_t nv = mesh.positions.size();
    if (!materials.empty() && materials.size() != nv)
        throw Error(path + ": " + std::to_string(materials.size()) + " material ids for " + std::to_string(nv) +
                    " vertices (need 0 or one per vertex)");
    const bool with_materials = !materials.empty();
    if (nv > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
        throw Error(path + ": " + std::to_string(nv) + " vertices exceed the PLY int index range");
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (const std::uint32_t v : mesh.triangles[t])
            if (v >= nv)
                throw Error(path + ": triangle " + std::to_string(t) + " references vertex " + std::to_string(v) +
                            " of " + std::to_string(nv));
    const std::string header = "ply\nformat binary_little_endian 1.0\ncomment tridex mesh, metres\nelement vertex " +
                               std::to_string(nv) +
                               "\nproperty float x\nproperty float y\nproperty float z\n" +
                               (with_materials ? "property uchar material\n" : "") + "element face " +
                               std::to_string(mesh.triangles.size()) +
                               "\nproperty list uchar int vertex_indices\nend_header\n";
    std::vector<char> body;
    body.reserve(nv * (with_materials ? 13 : 12) + mesh.triangles.size() * 13);
    for (std::size_t v = 0; v < nv; ++v) {
        const Vec3& p = mesh.positions[v];
        put_f32(body, static_cast<float>(p.x));
        put_f32(body, static_cast<float>(p.y));
        put_f32(body, static_cast<float>(p.z));
        if (with_materials) body.push_back(static_cast<char>(materials[v]));
    }
    for (const auto& t : mesh.triangles) {
        body.push_back(static_cast<char>(3));
        for (const std::uint32_t v : t) put_u32(body, v);
    }
    AtomicFile f(path);  // whole or not at all
    f.write(header.data(), header.size());
    f.write(body.data(), body.size());
    f.commit();
}

}  // namespace tridex::compute
