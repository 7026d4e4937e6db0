// compute/mesh/mesh_io.cpp - OpenMesh reading into a plain polygon soup, then weld and check.
#include "compute/mesh/mesh_io.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>

#include <iostream>
#include <fstream>
#include <iterator>
#include <mutex>
#include <sstream>

#include "compute/mesh/mesh_precheck.hpp"
#include "compute/mesh/openmesh_log.hpp"
#include "compute/mesh/mesh_weld.hpp"
#include "core/error.hpp"

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

// True when `path` is an ASCII OFF file with '#' comments; `text` then gets its content with every comment (from
// '#' to the end of its line) removed.
bool off_has_comments(const std::string& path, std::string& text) {
    std::ifstream in(path, std::ios::binary);
    const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (all.find('#') == std::string::npos || all.find("BINARY") != std::string::npos) return false;
    text.clear();
    text.reserve(all.size());
    bool comment = false;
    for (const char c : all) {
        if (c == '#') comment = true;
        if (c == '\n') comment = false;
        if (!comment) text.push_back(c);
    }
    return true;
}

}  // namespace

TriMesh load_closed_mesh(const std::string& path) {
    const MeshFormat format = mesh_format_of(path);
    precheck_mesh_file(path, format);

    SoupImporter importer;
    {
        std::lock_guard<std::mutex> lock(CaptureOpenMeshLog::mutex());
        CaptureOpenMeshLog capture;
        OM::IO::Options options;
        // OpenMesh's OFF reader takes a '#' comment line for data (the OFF format allows comments; the precheck
        // skips them): an ASCII OFF with comments is read from a copy without them.
        std::string text;
        const bool strip = format == MeshFormat::kOff && off_has_comments(path, text);
        std::istringstream stripped(text);
        const bool ok = strip ? OM::IO::IOManager().read(stripped, ".off", importer, options)
                              : OM::IO::IOManager().read(path, importer, options);
        if (!ok) {
            const std::string why = capture.first_line();
            throw Error(path + ": cannot parse mesh file" + (why.empty() ? std::string() : " (" + why + ")"));
        }
    }
    if (importer.bad_faces > 0)
        throw Error(path + ": " + std::to_string(importer.bad_faces) +
                    " faces with fewer than 3 vertices or out-of-range vertex indices");
    for (std::size_t i = 0; i < importer.soup.positions.size(); ++i)
        if (!is_finite(importer.soup.positions[i]))
            throw Error(path + ": vertex " + std::to_string(i) + " has a non-finite coordinate");
    if (importer.soup.triangles.empty()) throw Error(path + ": no triangles");

    TriMesh mesh = weld_exact(importer.soup);
    require_closed_outward(mesh, path);
    return mesh;
}

}  // namespace tridex::compute
