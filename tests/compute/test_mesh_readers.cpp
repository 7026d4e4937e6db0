// tests/compute/test_mesh_readers.cpp - the strict OFF and PLY readers: every variant they accept, every malformed
// file they refuse (with the line or byte offset), and the same soup as OpenMesh on the shared meshes.
#include <gtest/gtest.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "compute/mesh/mesh_text.hpp"
#include "compute/mesh/off_reader.hpp"
#include "compute/mesh/openmesh_log.hpp"
#include "compute/mesh/ply_reader.hpp"
#include "core/error.hpp"
#include "core/text/printable.hpp"

namespace fs = std::filesystem;
using tridex::Error;
using tridex::TriMesh;
using tridex::compute::read_off;
using tridex::compute::read_ply;

namespace {

std::string shared_data() {
    const char* d = std::getenv("TRIDEX_SHARED_DATA");
    return d ? d : "../shared/data";
}

template <class Reader>
std::string refusal(Reader read, const std::string& bytes, const std::string& name) {
    try {
        read(name, bytes);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

std::string off_refusal(const std::string& bytes) { return refusal(read_off, bytes, "m.off"); }
std::string ply_refusal(const std::string& bytes) { return refusal(read_ply, bytes, "m.ply"); }

const char* kTetVerts = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
const char* kTetFaces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
const int kTetFaceIds[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

void expect_tetrahedron(const TriMesh& m) {
    ASSERT_EQ(m.positions.size(), 4u);
    ASSERT_EQ(m.triangles.size(), 4u);
    EXPECT_EQ(m.positions[1], tridex::Vec3(1, 0, 0));
    EXPECT_EQ(m.positions[3], tridex::Vec3(0, 0, 1));
    for (int f = 0; f < 4; ++f)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(m.triangles[f][k], static_cast<std::uint32_t>(kTetFaceIds[f][k]));
}

void put_be32(std::string& s, std::uint32_t v) {
    for (int i = 3; i >= 0; --i) s.push_back(static_cast<char>(v >> (8 * i)));
}
void put_be_float(std::string& s, float v) { put_be32(s, std::bit_cast<std::uint32_t>(v)); }

/// A binary OFF tetrahedron (big-endian, as Geomview's manual says), with `colours` colour floats per face.
std::string binary_off_tet(int colours) {
    std::string s = "OFF BINARY # a comment on the header line\n";
    put_be32(s, 4);
    put_be32(s, 4);
    put_be32(s, 0);
    const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const auto& p : v)
        for (float x : p) put_be_float(s, x);
    for (const auto& f : kTetFaceIds) {
        put_be32(s, 3);
        for (int i : f) put_be32(s, static_cast<std::uint32_t>(i));
        put_be32(s, static_cast<std::uint32_t>(colours));
        for (int c = 0; c < colours; ++c) put_be_float(s, 0.5f);
    }
    return s;
}

/// A PLY tetrahedron header with the given format line and extra lines before the vertex element.
std::string ply_header(const std::string& format, const std::string& before = "") {
    return "ply\n" + format + "\n" + before +
           "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
           "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
}

}  // namespace

TEST(MeshReaders, OffVariantsOfTheHeaderAllGiveTheTetrahedron) {
    expect_tetrahedron(read_off("a.off", std::string("OFF\n4 4 0\n") + kTetVerts + kTetFaces));
    // No keyword (allowed by the manual), the counts on the keyword's line, vertices packed on one line.
    expect_tetrahedron(read_off("b.off", std::string("4 4 0\n0 0 0 1 0 0 0 1 0 0 0 1\n") + kTetFaces));
    expect_tetrahedron(read_off("c.off", std::string("OFF 4 4 0\n") + kTetVerts + kTetFaces));
    // Normals and colours per vertex, colours per face, comments.
    expect_tetrahedron(read_off("d.off", "NOFF\n4 4 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n0 0 1 0 0 1\n" + std::string(kTetFaces)));
    expect_tetrahedron(read_off("e.off", "COFF # coloured\n4 4 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n"
                                         "0 1 0 0 0 255 255\n0 0 1 9 9 9 255\n3 0 2 1 1 0 0\n3 0 1 3 0.5 0.5 0.5 1\n"
                                         "3 0 3 2 7\n# a comment line\n3 1 2 3\n"));
    // Homogeneous coordinates are divided out; nOFF gives the dimension.
    expect_tetrahedron(read_off("f.off", std::string("4OFF\n4 4 0\n0 0 0 2\n2 0 0 2\n0 4 0 4\n0 0 0.5 0.5\n") + kTetFaces));
    expect_tetrahedron(read_off("g.off", std::string("nOFF 3\n4 4 0\n") + kTetVerts + kTetFaces));
    const TriMesh quad = read_off("q.off", "OFF\n5 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n9 9 9\n4 0 1 2 3\n");
    EXPECT_EQ(quad.triangles.size(), 2u);  // fan-triangulated
}

TEST(MeshReaders, BinaryOffIsReadBigEndianWithFaceColours) {
    expect_tetrahedron(read_off("b.off", binary_off_tet(0)));
    expect_tetrahedron(read_off("c.off", binary_off_tet(4)));
    std::string truncated = binary_off_tet(4);
    truncated.resize(truncated.size() - 6);
    const std::string msg = off_refusal(truncated);
    EXPECT_NE(msg.find("m.off: byte "), std::string::npos) << msg;
    EXPECT_NE(msg.find("the file ends in a face"), std::string::npos) << msg;
    std::string bad_colour = binary_off_tet(0);
    bad_colour[bad_colour.size() - 1] = 9;  // the last face's colour count
    EXPECT_NE(off_refusal(bad_colour).find("face 3 colour count 9 is not 0 to 4"), std::string::npos);
    EXPECT_EQ(off_refusal("nOFF 3 BINARY\n"), "m.off: OFF header: nOFF BINARY is not supported (write the file as ASCII)");
}

TEST(MeshReaders, OffRefusalsNameTheLine) {
    const std::string head = std::string("OFF\n4 4 0\n") + kTetVerts;
    EXPECT_EQ(off_refusal(head + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 7\n"), "m.off:10: face 3 vertex index '7' is not in 0..3");
    EXPECT_EQ(off_refusal(head + "3 0 2 1\n2 0 1\n3 0 3 2\n3 1 2 3\n"), "m.off:8: face 1 has 2 vertices (needs at least 3)");
    EXPECT_EQ(off_refusal("OFF\n4 4 0\n0.0 0.0 0.0\n1.0 0.0 0.0\n0.0 1.0 0.0\n0.0 0.0 1.0\n3 0 2 1\n3 0 1 3\n3 0 3 2\n"),
              "m.off:10: the file ends before face 3 of 4");
    EXPECT_EQ(off_refusal(head + "3 0 2 1\nx 0 1 3\n3 0 3 2\n3 1 2 3\n"),
              "m.off:8: face 1 vertex count 'x' is not a non-negative integer");
    EXPECT_EQ(off_refusal("OFF\n4 4 0\n0 0 0\n1 0 0\n0 1e999 0\n0 0 1\n" + std::string(kTetFaces)),
              "m.off:5: vertex 2 coordinate '1e999' is not a finite number");
    EXPECT_EQ(off_refusal(std::string("4OFF\n4 4 0\n0 0 0 0\n1 0 0 1\n0 1 0 1\n0 0 1 1\n") + kTetFaces),
              "m.off:3: vertex 0 has a homogeneous coordinate of 0");
    EXPECT_EQ(off_refusal("XOFF\n"), "m.off: OFF header: unknown keyword 'XOFF' (expected [ST][C][N][4][n]OFF)");
    EXPECT_EQ(off_refusal("nOFF 2\n"), "m.off: OFF header: bad vertex dimension '2' (3 to 64)");
}

TEST(MeshReaders, AbsurdCountsAreRefusedBeforeAnythingIsAllocated) {
    // A face claiming three billion vertices in a file of a few bytes, in each format.
    const std::string off = std::string("OFF\n4 4 0\n") + kTetVerts + "3000000000 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    EXPECT_EQ(off_refusal(off), "m.off:7: face 0 claims 3000000000 vertices, more than the 31 bytes left can hold");
    std::string off_bin = binary_off_tet(0);
    const std::size_t first_face = off_bin.size() - 4 * 20;
    off_bin[first_face] = 0x7f;  // face 0's count becomes 0x7f000003
    EXPECT_NE(off_refusal(off_bin).find("face 0 claims 2130706435 vertices"), std::string::npos) << off_refusal(off_bin);
    std::string ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                      "element face 4\nproperty list uint int vertex_indices\nend_header\n" +
                      std::string(kTetVerts) + "3000000000 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    EXPECT_EQ(ply_refusal(ply),
              "m.ply:14: face 0 property 'vertex_indices' claims 3000000000 items, more than the 31 bytes left can hold");
    std::string ply_bin = ply_header("format binary_little_endian 1.0");
    const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    ply_bin.append(reinterpret_cast<const char*>(v), sizeof v);
    ply_bin.push_back(static_cast<char>(200));  // uchar count 200: 800 bytes of indices in a file that has 12
    ply_bin.append(12, '\0');
    EXPECT_NE(ply_refusal(ply_bin).find("face 0 property 'vertex_indices' claims 200 items"), std::string::npos);
    EXPECT_EQ(ply_refusal("ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n"),
              "m.ply: PLY header declares more elements than a file of 75 bytes can hold");
}

TEST(MeshReaders, PlyHeaderStructureIsChecked) {
    const std::string body = std::string(kTetVerts) + kTetFaces;
    expect_tetrahedron(read_ply("a.ply", ply_header("format ascii 1.0", "comment made by hand\nobj_info none\n") + body));
    EXPECT_EQ(ply_refusal("ply\nformat ascii 1.0\nproperty float x\nelement vertex 4\n"),
              "m.ply:3: PLY header: a property before any element");
    EXPECT_EQ(ply_refusal(ply_header("format ascii") + body), "m.ply:2: PLY header: the format line needs 'format KIND 1.0'");
    EXPECT_EQ(ply_refusal(ply_header("format binary_little_endian") + body),
              "m.ply:2: PLY header: the format line needs 'format KIND 1.0'");
    EXPECT_EQ(ply_refusal(ply_header("format ascii 2.0") + body), "m.ply:2: PLY header: unknown version '2.0' (expected 1.0)");
    EXPECT_EQ(ply_refusal(ply_header("format text 1.0") + body), "m.ply:2: PLY header: unknown format 'text'");
    EXPECT_EQ(ply_refusal("ply\nelement vertex 4\nformat ascii 1.0\n"),
              "m.ply:2: PLY header has no format line before its first element");
    EXPECT_EQ(ply_refusal("ply\nformat ascii 1.0\nformat ascii 1.0\n"), "m.ply:3: PLY header: a second format line");
    EXPECT_EQ(ply_refusal("ply\nformat ascii 1.0\nelement vertex 4\nproperty list float int v\n"),
              "m.ply:4: PLY header: bad list property types 'float int' (the count must be an integer type)");
    EXPECT_EQ(ply_refusal("ply\nformat ascii 1.0\nelement vertex 4\nproperty half x\n"),
              "m.ply:4: PLY header: unknown property type 'half'");
    EXPECT_EQ(ply_refusal("ply\nformat ascii 1.0\nelement vertex -4\n"),
              "m.ply:3: PLY header: element 'vertex' count '-4' is not a non-negative integer");
    EXPECT_EQ(ply_refusal("ply\nformat ascii 1.0\nelement vertex 4\n"), "m.ply: PLY header has no end_header line");
    EXPECT_EQ(ply_refusal("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nend_header\n"),
              "m.ply: PLY header: no element 'vertex' with properties x, y and z");
    EXPECT_EQ(ply_refusal("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                          "end_header\n"),
              "m.ply: PLY header: no element 'face' with a list property 'vertex_indices'");
    EXPECT_EQ(ply_refusal("solid\n"), "m.ply: not a PLY file (missing 'ply' magic line)");
}

TEST(MeshReaders, PlyBodyRefusalsNameTheLineOrByte) {
    const std::string head = ply_header("format ascii 1.0");
    EXPECT_EQ(ply_refusal(head + "0 0 0\n1 0 0\n0 nan 0\n0 0 1\n" + kTetFaces),
              "m.ply:12: vertex 2 property 'y' is not a finite number");
    EXPECT_EQ(ply_refusal(head + kTetVerts + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 4\n"),
              "m.ply:17: face 3 vertex index 4 is not in 0..3");
    EXPECT_EQ(ply_refusal(head + kTetVerts + "3 0 2 1\n256 0 1 3\n"),
              "m.ply:15: face 1 property 'vertex_indices' count '256' is not an integer in 0..255");
    EXPECT_EQ(ply_refusal(head + kTetVerts + "3 0 2 1\n"), "m.ply:15: the file ends in face 1 property 'vertex_indices' count");
    std::string bin = ply_header("format binary_big_endian 1.0");
    bin.append(48, '\0');
    bin.append(4, '\0');  // face 0 lists no vertices
    const std::string msg = ply_refusal(bin);
    EXPECT_EQ(msg.rfind("m.ply: byte ", 0), 0u) << msg;
    EXPECT_NE(msg.find("face 0 has 0 vertices (needs at least 3)"), std::string::npos) << msg;
}

TEST(MeshReaders, PlyBigEndianWithOtherElementsAndProperties) {
    // binary_big_endian, a material element before the vertices, extra scalar and list properties.
    std::string ply = "ply\nformat binary_big_endian 1.0\nelement material 1\nproperty uchar red\n"
                      "element vertex 4\nproperty double z\nproperty float x\nproperty list uchar short tags\n"
                      "property float y\nelement face 4\nproperty int flags\nproperty list uchar uint vertex_indices\n"
                      "end_header\n";
    ply.push_back(7);
    const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const auto& p : v) {
        const auto z = std::bit_cast<std::uint64_t>(static_cast<double>(p[2]));
        put_be32(ply, static_cast<std::uint32_t>(z >> 32));
        put_be32(ply, static_cast<std::uint32_t>(z));
        put_be_float(ply, p[0]);
        ply.push_back(2);
        ply.append("\x00\x01\x00\x02", 4);
        put_be_float(ply, p[1]);
    }
    for (const auto& f : kTetFaceIds) {
        put_be32(ply, 0xffffffffu);
        ply.push_back(3);
        for (int i : f) put_be32(ply, static_cast<std::uint32_t>(i));
    }
    expect_tetrahedron(read_ply("be.ply", ply));
}

TEST(MeshReaders, RefusalsNeverEchoControlCharacters) {
    const std::string head = ply_header("format ascii 1.0");
    const std::string msg = ply_refusal(head + "0 0 0\n1 0 0\n0 1 \x1b[31m0\n0 0 1\n" + kTetFaces);
    EXPECT_EQ(msg, "m.ply:12: vertex 2 property 'z' '\\x1b[31m0' is not a number");
    const std::string off = off_refusal("\x07\x08OFF\r\n");
    for (char c : off) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << off;
    EXPECT_EQ(tridex::printable("a\nb\\c\xff", 32), "a\\x0ab\\\\c\\xff");
    EXPECT_EQ(tridex::printable(std::string(40, 'x'), 4), "xxxx...");
}

// Every OFF and PLY among the shared meshes gives the soup OpenMesh's readers give: the same faces, and positions
// equal to OpenMesh's single-precision ones within their rounding.
TEST(MeshReaders, SharedMeshesGiveOpenMeshsSoup) {
    int files = 0;
    for (const auto& entry : fs::directory_iterator(shared_data() + "/meshes")) {
        const std::string path = entry.path().string();
        const std::string ext = entry.path().extension().string();
        if (ext != ".off" && ext != ".ply") continue;
        SCOPED_TRACE(path);
        const std::string bytes = tridex::compute::read_file_bytes(path);
        const TriMesh ours = ext == ".off" ? read_off(path, bytes) : read_ply(path, bytes);
        OpenMesh::PolyMesh_ArrayKernelT<> om;
        {
            std::lock_guard<std::mutex> lock(tridex::compute::CaptureOpenMeshLog::mutex());
            tridex::compute::CaptureOpenMeshLog quiet;  // OpenMesh's complaints about Wuson.ply's free-text line
            ASSERT_TRUE(OpenMesh::IO::read_mesh(om, path));
        }
        EXPECT_EQ(ours.positions.size(), om.n_vertices());
        std::size_t om_triangles = 0;
        for (const auto f : om.faces()) om_triangles += om.valence(f) - 2;
        // OpenMesh drops faces it cannot add to a manifold mesh; ours keeps every face of the file.
        EXPECT_GE(ours.triangles.size(), om_triangles);
        if (ours.positions.size() != om.n_vertices()) continue;
        double worst = 0.0;
        for (std::size_t i = 0; i < ours.positions.size(); ++i) {
            const auto p = om.point(OpenMesh::VertexHandle(static_cast<int>(i)));
            for (int k = 0; k < 3; ++k)
                worst = std::max(worst, std::abs(ours.positions[i][k] - p[k]) / std::max(1.0, std::abs(ours.positions[i][k])));
        }
        EXPECT_LT(worst, 1e-6);
        ++files;
    }
    EXPECT_GE(files, 6);
}
