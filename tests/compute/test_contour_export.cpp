// Tests of compute/mesh/mesh_export: binary PLY written by write_ply reads back with OpenMesh unchanged.
#include <gtest/gtest.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "compute/contour/contour_dual.hpp"
#include "compute/mesh/mesh_export.hpp"
#include "core/error.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;
using OmMesh = OpenMesh::TriMesh_ArrayKernelT<>;

std::string temp_path(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("tridex_contour_" + std::to_string(::getpid()) + "_" + name)).string();
}

TEST(ContourExport, PlyRoundTripThroughOpenMesh) {
    TriDexel model = empty_model(cube_lattice(32));
    fill_rays(model, [](int a, int u, int v) { return sphere_chord(Vec3(15.7, 16.2, 16.1), 11.3, a, u, v); });
    Contourer contourer(model);
    contourer.update(model);
    const TriMesh m = contourer.mesh();
    const std::string path = temp_path("sphere.ply");
    write_ply(path, m);

    // Size: header + 12 bytes per vertex + 13 bytes per triangle.
    std::ifstream in(path, std::ios::binary);
    std::string header, line;
    while (std::getline(in, line)) {
        header += line + "\n";
        if (line == "end_header") break;
    }
    EXPECT_NE(header.find("format binary_little_endian 1.0"), std::string::npos);
    EXPECT_EQ(std::filesystem::file_size(path), header.size() + 12 * m.positions.size() + 13 * m.triangles.size());

    OmMesh om;
    OpenMesh::IO::Options opt = OpenMesh::IO::Options::Binary | OpenMesh::IO::Options::LSB;
    ASSERT_TRUE(OpenMesh::IO::read_mesh(om, path, opt));
    ASSERT_EQ(om.n_vertices(), m.positions.size());
    ASSERT_EQ(om.n_faces(), m.triangles.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        const auto p = om.point(OmMesh::VertexHandle(static_cast<int>(i)));
        for (int a = 0; a < 3; ++a)  // float rounding of metres: half an ulp, < 2^-24 relative
            ASSERT_NEAR(p[a], m.positions[i][a], std::abs(m.positions[i][a]) * 6e-8 + 1e-12) << i;
    }
    for (std::size_t f = 0; f < m.triangles.size(); ++f) {
        std::array<std::uint32_t, 3> got{};
        int k = 0;
        for (auto v : om.fv_range(OmMesh::FaceHandle(static_cast<int>(f)))) got[k++] = static_cast<std::uint32_t>(v.idx());
        // Same cyclic order (OpenMesh may start the face at another vertex).
        const auto& want = m.triangles[f];
        const bool same = (got == want) || (got == std::array<std::uint32_t, 3>{want[1], want[2], want[0]}) ||
                          (got == std::array<std::uint32_t, 3>{want[2], want[0], want[1]});
        ASSERT_TRUE(same) << "face " << f;
    }
    std::filesystem::remove(path);
}

TEST(ContourExport, UnwritablePathThrowsNamingIt) {
    TriMesh m;
    m.positions = {Vec3(0.0), Vec3(1.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0)};
    m.triangles = {{0, 1, 2}};
    const std::string path = "/nonexistent-dir-tridex/out.ply";
    try {
        write_ply(path, m);
        FAIL() << "no throw";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
    }
}

TEST(ContourExport, BadIndexThrowsAndWritesNothing) {
    TriMesh m;
    m.positions = {Vec3(0.0), Vec3(1.0, 0.0, 0.0)};
    m.triangles = {{0, 1, 2}};
    const std::string path = temp_path("bad.ply");
    EXPECT_THROW(write_ply(path, m), Error);
    EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace tridex::compute
