// compute/mesh/mesh_write.cpp - OpenMesh writers (STL binary, OBJ, PLY binary) into memory, then an atomic file.
#include "compute/mesh/mesh_write.hpp"

// GCC 12 reports OpenMesh's own PropertyT<VectorT<uchar, 3>>::push_back (the vertex colours) as maybe
// uninitialised, a false positive inside the library's header.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <algorithm>
#include <cctype>
#include <sstream>
#include <vector>

#include "compute/mesh/openmesh_log.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace tridex::compute {

namespace {

namespace OM = OpenMesh;
using OmMesh = OM::TriMesh_ArrayKernelT<>;

std::string extension_of(const std::string& path) {
    const std::size_t slash = path.find_last_of('/'), dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

}  // namespace

MeshFileFormat mesh_file_format(const std::string& path) {
    const std::string ext = extension_of(path);
    if (ext == "stl") return MeshFileFormat::kStl;
    if (ext == "obj") return MeshFileFormat::kObj;
    if (ext == "ply") return MeshFileFormat::kPly;
    if (ext.empty()) throw Error(path + ": no file extension to tell the mesh format; use .stl, .obj or .ply");
    throw Error(path + ": unknown mesh format '." + ext + "'; use .stl, .obj or .ply");
}

void write_mesh_file(const std::string& path, const TriMesh& mesh, std::span<const std::array<std::uint8_t, 3>> colours) {
    const MeshFileFormat format = mesh_file_format(path);
    const std::size_t nv = mesh.positions.size();
    if (mesh.triangles.empty()) throw Error(path + ": the mesh is empty (nothing written)");
    if (!colours.empty() && colours.size() != nv)
        throw Error(path + ": " + std::to_string(colours.size()) + " colours for " + std::to_string(nv) + " vertices");
    const bool with_colours = format == MeshFileFormat::kPly && !colours.empty();

    OmMesh om;
    if (with_colours) om.request_vertex_colors();
    std::vector<OmMesh::VertexHandle> vh(nv);
    for (std::size_t i = 0; i < nv; ++i) {
        const Vec3& p = mesh.positions[i];
        vh[i] = om.add_vertex(OmMesh::Point(static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)));
        if (with_colours) om.set_color(vh[i], OmMesh::Color(colours[i][0], colours[i][1], colours[i][2]));
    }
    for (const auto& t : mesh.triangles) {
        for (auto idx : t)
            if (static_cast<std::size_t>(idx) >= nv) throw Error(path + ": a triangle indexes vertex " + std::to_string(idx) + " of " + std::to_string(nv));
        if (!om.add_face(vh[t[0]], vh[t[1]], vh[t[2]]).is_valid())
            throw Error(path + ": the mesh is not a 2-manifold (OpenMesh refused a triangle; nothing written)");
    }
    OM::IO::Options opt;
    std::string ext = "ply";
    if (format == MeshFileFormat::kStl) {
        opt += OM::IO::Options::Binary;
        ext = "stl";
        om.request_face_normals();
        om.update_face_normals();
    } else if (format == MeshFileFormat::kObj) {
        ext = "obj";
    } else {
        opt += OM::IO::Options::Binary;
        opt += OM::IO::Options::LSB;
        if (with_colours) opt += OM::IO::Options::VertexColor;
    }
    std::ostringstream bytes(std::ios::out | std::ios::binary);
    {
        std::lock_guard<std::mutex> lock(CaptureOpenMeshLog::mutex());
        CaptureOpenMeshLog capture;
        if (!OM::IO::write_mesh(om, bytes, ext, opt, 9)) {
            const std::string why = capture.first_line();
            throw Error(path + ": OpenMesh could not write the ." + ext + " data" + (why.empty() ? "" : " (" + why + ")") +
                        "; nothing written");
        }
    }
    const std::string data = bytes.str();
    AtomicFile file(path);
    file.write(data.data(), data.size());
    file.commit();
}

}  // namespace tridex::compute

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
