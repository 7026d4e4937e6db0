// compute/mesh/mesh_io.cpp - a polygon soup from our OFF and PLY readers or OpenMesh (OBJ, STL), then weld and check.
#include "compute/mesh/mesh_io.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>

#include <mutex>

#include "compute/mesh/mesh_precheck.hpp"
#include "compute/mesh/mesh_text.hpp"
#include "compute/mesh/off_reader.hpp"
#include "compute/mesh/ply_reader.hpp"
#include "compute/mesh/openmesh_log.hpp"
#include "compute/mesh/mesh_weld.hpp"
#include "core/error.hpp"
#include "core/text/printable.hpp"

namespace tridex::compute {
namespace {

namespace OM = OpenMesh;

/// An OpenMesh importer that records vertex positions and fan-triangulated faces and ignores
/// everything else (normals, colours, texture data). Unlike an OpenMesh mesh it accepts any
/// topology, so non-manifold or open input reaches our own checks with exact counts.
class SoupImporter final : public OM::IO::BaseImporter {
public:
    TriMesh soup;
    std::size_t faces = 0;
    std::size_t bad_faces = 0;  ///< faces with an out-of-range vertex handle or < 3 vertices

    OM::VertexHandle add_vertex(const OM::Vec3f& p) override { return push(Vec3(p[0], p[1], p[2])); }
    OM::VertexHandle add_vertex(const OM::Vec3d& p) override { return push(Vec3(p[0], p[1], p[2])); }
    OM::VertexHandle add_vertex() override { return push(Vec3(0.0)); }
    OM::HalfedgeHandle add_edge(OM::VertexHandle, OM::VertexHandle) override { return OM::HalfedgeHandle(); }
    OM::FaceHandle add_face(const VHandles& ids) override {
        const auto n = static_cast<long long>(soup.positions.size());
        bool ok = ids.size() >= 3;
        for (const auto& v : ids) ok = ok && v.idx() >= 0 && v.idx() < n;
        if (!ok) {
            ++bad_faces;
            return OM::FaceHandle();
        }
        for (std::size_t k = 1; k + 1 < ids.size(); ++k)
            soup.triangles.push_back({static_cast<std::uint32_t>(ids[0].idx()), static_cast<std::uint32_t>(ids[k].idx()),
                                      static_cast<std::uint32_t>(ids[k + 1].idx())});
        return OM::FaceHandle(static_cast<int>(faces++));
    }
    OM::FaceHandle add_face(OM::HalfedgeHandle) override { return OM::FaceHandle(); }
    void add_face_texcoords(OM::FaceHandle, OM::VertexHandle, const std::vector<OM::Vec2f>&) override {}
    void add_face_texcoords(OM::FaceHandle, OM::VertexHandle, const std::vector<OM::Vec3f>&) override {}
    void set_face_texindex(OM::FaceHandle, int) override {}
    void set_point(OM::VertexHandle v, const OM::Vec3f& p) override {
        if (v.idx() >= 0 && static_cast<std::size_t>(v.idx()) < soup.positions.size()) soup.positions[v.idx()] = Vec3(p[0], p[1], p[2]);
    }
    void set_halfedge(OM::VertexHandle, OM::HalfedgeHandle) override {}
    void set_normal(OM::VertexHandle, const OM::Vec3f&) override {}
    void set_normal(OM::VertexHandle, const OM::Vec3d&) override {}
    void set_color(OM::VertexHandle, const OM::Vec3uc&) override {}
    void set_color(OM::VertexHandle, const OM::Vec4uc&) override {}
    void set_color(OM::VertexHandle, const OM::Vec3f&) override {}
    void set_color(OM::VertexHandle, const OM::Vec4f&) override {}
    void set_texcoord(OM::VertexHandle, const OM::Vec2f&) override {}
    void set_status(OM::VertexHandle, const OM::Attributes::StatusInfo&) override {}
    void set_next(OM::HalfedgeHandle, OM::HalfedgeHandle) override {}
    void set_face(OM::HalfedgeHandle, OM::FaceHandle) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(OM::HalfedgeHandle, const OM::Vec2f&) override {}
    void set_texcoord(OM::VertexHandle, const OM::Vec3f&) override {}
    void set_texcoord(OM::HalfedgeHandle, const OM::Vec3f&) override {}
    void set_status(OM::HalfedgeHandle, const OM::Attributes::StatusInfo&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec3uc&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec4uc&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec3f&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec4f&) override {}
    void set_status(OM::EdgeHandle, const OM::Attributes::StatusInfo&) override {}
    void set_normal(OM::FaceHandle, const OM::Vec3f&) override {}
    void set_normal(OM::FaceHandle, const OM::Vec3d&) override {}
    void set_color(OM::FaceHandle, const OM::Vec3uc&) override {}
    void set_color(OM::FaceHandle, const OM::Vec4uc&) override {}
    void set_color(OM::FaceHandle, const OM::Vec3f&) override {}
    void set_color(OM::FaceHandle, const OM::Vec4f&) override {}
    void set_status(OM::FaceHandle, const OM::Attributes::StatusInfo&) override {}
    void add_texture_information(int, std::string) override {}
    std::size_t n_vertices() const override { return soup.positions.size(); }
    std::size_t n_faces() const override { return faces; }
    std::size_t n_edges() const override { return 0; }

private:
    OM::VertexHandle push(const Vec3& p) {
        soup.positions.push_back(p);
        return OM::VertexHandle(static_cast<int>(soup.positions.size() - 1));
    }
};

/// The polygon soup of an OBJ or STL file, read by OpenMesh (the file already prechecked).
TriMesh read_with_openmesh(const std::string& path) {
    SoupImporter importer;
    std::lock_guard<std::mutex> lock(CaptureOpenMeshLog::mutex());
    CaptureOpenMeshLog capture;
    OM::IO::Options options;
    if (!OM::IO::IOManager().read(path, importer, options)) {
        const std::string why = capture.first_line();
        throw Error(path + ": cannot parse mesh file" + (why.empty() ? std::string() : " (" + printable(why, 200) + ")"));
    }
    if (importer.bad_faces > 0)
        throw Error(path + ": " + std::to_string(importer.bad_faces) +
                    " faces with fewer than 3 vertices or out-of-range vertex indices");
    return std::move(importer.soup);
}

}  // namespace

TriMesh load_closed_mesh(const std::string& path) {
    const MeshFormat format = mesh_format_of(path);
    precheck_mesh_file(path, format);

    TriMesh soup;
    if (format == MeshFormat::kOff || format == MeshFormat::kPly) {
        const std::string bytes = read_file_bytes(path);
        soup = format == MeshFormat::kOff ? read_off(path, bytes) : read_ply(path, bytes);
    } else {
        soup = read_with_openmesh(path);
    }
    return closed_mesh_from_soup(soup, path);
}

TriMesh closed_mesh_from_soup(const TriMesh& soup, const std::string& path) {
    for (std::size_t i = 0; i < soup.positions.size(); ++i)
        if (!is_finite(soup.positions[i]))
            throw Error(path + ": vertex " + std::to_string(i) + " has a non-finite coordinate");
    if (soup.triangles.empty()) throw Error(path + ": no triangles");

    TriMesh mesh = weld_exact(soup);
    require_closed_outward(mesh, path);
    return mesh;
}

}  // namespace tridex::compute
