// tests/compute/test_mesh_io.cpp - load_closed_mesh on the shared meshes, the bad files, and small
// hand-written files for each refusal reason.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <array>
#include <map>
#include <sstream>
#include <string>

#include "compute/mesh/mesh_io.hpp"
#include "compute/mesh/mesh_weld.hpp"
#include "core/primitives.hpp"
#include "core/error.hpp"

namespace fs = std::filesystem;
using tridex::Error;
using tridex::TriMesh;
using tridex::compute::load_closed_mesh;

namespace {

std::string shared_data() {
    const char* d = std::getenv("TRIDEX_SHARED_DATA");
    return d ? d : "../shared/data";
}

/// Writes `text` to a fresh file named `name` in the test's temporary directory; returns its path.
std::string write_temp(const std::string& name, const std::string& text) {
    const fs::path dir = fs::path(testing::TempDir()) / ("tridex_mesh_io_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path p = dir / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
}

/// The message of the tridex::Error that loading `path` throws ("" if it loads).
std::string refusal(const std::string& path) {
    try {
        load_closed_mesh(path);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

/// Boundary edges of an OFF file, counted independently of the loader (undirected edge use counts).
std::size_t off_boundary_edges(const std::string& path) {
    std::ifstream in(path);
    std::string key;
    std::size_t nv = 0, nf = 0, ne = 0;
    in >> key >> nv >> nf >> ne;
    for (std::size_t i = 0; i < 3 * nv; ++i) {
        double x;
        in >> x;
    }
    std::map<std::pair<long, long>, int> uses;
    for (std::size_t f = 0; f < nf; ++f) {
        std::size_t k;
        in >> k;
        std::vector<long> ids(k);
        for (auto& id : ids) in >> id;
        for (std::size_t j = 0; j < k; ++j) {
            const long a = ids[j], b = ids[(j + 1) % k];
            ++uses[{std::min(a, b), std::max(a, b)}];
        }
    }
    std::size_t boundary = 0;
    for (const auto& [e, n] : uses) boundary += n == 1;
    return boundary;
}

const char* kTetVerts = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";

}  // namespace

TEST(MeshIo, EveryBadFileIsRefusedWithItsPath) {
    std::size_t files = 0;
    for (const auto& entry : fs::directory_iterator(shared_data() + "/bad")) {
        const std::string path = entry.path().string();
        const std::string msg = refusal(path);
        SCOPED_TRACE(path);
        EXPECT_FALSE(msg.empty());
        EXPECT_EQ(msg.rfind(path, 0), 0u) << msg;  // the message starts with the path
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        std::cout << "[ refused  ] " << msg << "\n";
        ++files;
    }
    EXPECT_EQ(files, 6u);
}

TEST(MeshIo, BadFilesGiveTheirReasons) {
    const std::string bad = shared_data() + "/bad/";
    EXPECT_NE(refusal(bad + "OutOfMemory.off").find("OFF header claims 353535235358 vertices and 6 faces, impossible in a file of 309 bytes"),
              std::string::npos);
    EXPECT_NE(refusal(bad + "empty.off").find("file is empty"), std::string::npos);
    EXPECT_NE(refusal(bad + "empty.obj").find("file is empty"), std::string::npos);
    EXPECT_NE(refusal(bad + "empty.ply").find("file is empty"), std::string::npos);
    // malformed.obj: "f 4 12 2 1" on line 23 references vertex 12 of 8.
    EXPECT_NE(refusal(bad + "malformed.obj").find("malformed.obj:23: face vertex index 12 out of range (8 vertices"),
              std::string::npos);
    // malformed2.obj: a bare "f" on line 23.
    EXPECT_NE(refusal(bad + "malformed2.obj").find("malformed2.obj:23: face with 0 vertex references"), std::string::npos);
}

TEST(MeshIo, OpenElephantGivesBoundaryEdgeCount) {
    const std::string path = shared_data() + "/meshes/elephant-with-holes.off";
    const std::size_t expected = off_boundary_edges(path);
    ASSERT_GT(expected, 0u);
    const std::string msg = refusal(path);
    EXPECT_EQ(msg, path + ": mesh is not closed: " + std::to_string(expected) + " boundary edges");
}

// Wuson.ply is a triangle soup (3 own vertices per triangle). Welding exactly coincident positions
// leaves 2117 vertices, but the model still has holes: 52 separate boundary loops (an open body and
// 50 small open pieces), so it must be refused with the boundary count of the welded mesh. The count
// is recomputed here from the text, welding on the exact coordinate strings.
TEST(MeshIo, WusonSoupIsWeldedButStillOpen) {
    const std::string path = shared_data() + "/meshes/Wuson.ply";
    std::ifstream in(path);
    std::string line;
    std::size_t nv = 0, nf = 0;
    while (std::getline(in, line) && line != "end_header") {
        std::istringstream ls(line);
        std::string w, what;
        ls >> w >> what;
        if (w == "element" && what == "vertex") ls >> nv;
        if (w == "element" && what == "face") ls >> nf;
    }
    ASSERT_EQ(nv, 11184u);
    ASSERT_EQ(nf, 3732u);
    std::map<std::string, long> weld;
    std::vector<long> id(nv);
    for (std::size_t i = 0; i < nv; ++i) {
        std::getline(in, line);
        std::istringstream ls(line);
        std::string x, y, z;
        ls >> x >> y >> z;
        id[i] = weld.emplace(x + " " + y + " " + z, static_cast<long>(weld.size())).first->second;
    }
    std::map<std::pair<long, long>, int> uses;
    for (std::size_t f = 0; f < nf; ++f) {
        std::size_t k, a, b, c;
        in >> k >> a >> b >> c;
        ASSERT_EQ(k, 3u);
        const long w[3] = {id[a], id[b], id[c]};
        for (int j = 0; j < 3; ++j) ++uses[{std::min(w[j], w[(j + 1) % 3]), std::max(w[j], w[(j + 1) % 3])}];
    }
    std::size_t boundary = 0;
    for (const auto& [e, n] : uses) boundary += n == 1;
    EXPECT_EQ(weld.size(), 2117u);
    EXPECT_EQ(boundary, 412u);  // without welding every one of the 11196 edges would be a boundary edge
    EXPECT_EQ(refusal(path), path + ": mesh is not closed: 412 boundary edges");
}

TEST(MeshIo, WeldExactClosesABoxSoup) {
    const TriMesh box = tridex::box_mesh(tridex::Aabb{tridex::Vec3(-1.0, 0.0, -0.0), tridex::Vec3(1.0, 2.0, 3.0)});
    TriMesh soup;
    for (const auto& t : box.triangles) {
        const auto n = static_cast<std::uint32_t>(soup.positions.size());
        for (std::uint32_t v : t) soup.positions.push_back(box.positions[v] * 1.0);
        soup.triangles.push_back({n, n + 1, n + 2});
    }
    soup.positions[0].z = -0.0;  // -0 and +0 weld together
    soup.triangles.push_back({0, 0, 1});  // degenerate: dropped
    const TriMesh m = tridex::compute::weld_exact(soup);
    EXPECT_EQ(m.positions.size(), 8u);
    EXPECT_EQ(m.triangles.size(), 12u);
    const tridex::EdgeStats s = tridex::edge_stats(m);
    EXPECT_EQ(s.boundary_edges + s.nonmanifold_edges + s.misoriented_edges, 0u);
    EXPECT_DOUBLE_EQ(tridex::signed_volume(m), 12.0);  // 2 x 2 x 3
}

// Spider_binary.stl: 1368 facets; welding exactly equal float positions gives 722 vertices and 56
// degenerate facets, and leaves 72 boundary edges, so it is refused. Recounted here from the bytes.
TEST(MeshIo, SpiderBinaryStlIsOpen) {
    const std::string path = shared_data() + "/meshes/Spider_binary.stl";
    std::ifstream in(path, std::ios::binary);
    char head[84];
    ASSERT_TRUE(in.read(head, sizeof head));
    std::uint32_t n = 0;
    std::memcpy(&n, head + 80, 4);
    ASSERT_EQ(n, 1368u);
    std::map<std::array<float, 3>, long> weld;
    std::map<std::pair<long, long>, int> uses;
    std::size_t degenerate = 0;
    for (std::uint32_t f = 0; f < n; ++f) {
        char rec[50];
        ASSERT_TRUE(in.read(rec, sizeof rec));
        long id[3];
        for (int k = 0; k < 3; ++k) {
            std::array<float, 3> p;
            std::memcpy(p.data(), rec + 12 + 12 * k, 12);
            id[k] = weld.emplace(p, static_cast<long>(weld.size())).first->second;
        }
        if (id[0] == id[1] || id[1] == id[2] || id[2] == id[0]) {
            ++degenerate;
            continue;
        }
        for (int k = 0; k < 3; ++k) ++uses[{std::min(id[k], id[(k + 1) % 3]), std::max(id[k], id[(k + 1) % 3])}];
    }
    std::size_t boundary = 0, over = 0;
    for (const auto& [e, c] : uses) {
        boundary += c == 1;
        over += c > 2;
    }
    EXPECT_EQ(weld.size(), 722u);
    EXPECT_EQ(degenerate, 56u);
    EXPECT_EQ(over, 0u);
    EXPECT_EQ(boundary, 72u);
    const std::string msg = refusal(path);
    std::cout << "[ spider   ] " << msg << "\n";
    EXPECT_EQ(msg, path + ": mesh is not closed: 72 boundary edges");
}

TEST(MeshIo, SphereAndBunnyLoadClosed) {
    const TriMesh sphere = load_closed_mesh(shared_data() + "/meshes/sphere.off");
    EXPECT_EQ(sphere.positions.size(), 162u);
    EXPECT_EQ(sphere.triangles.size(), 320u);
    EXPECT_GT(tridex::signed_volume(sphere), 0.0);
    const TriMesh bunny = load_closed_mesh(shared_data() + "/meshes/bunny00.off");
    EXPECT_EQ(bunny.positions.size(), 37706u);
    EXPECT_EQ(bunny.triangles.size(), 75408u);
    EXPECT_GT(tridex::signed_volume(bunny), 0.0);
}

TEST(MeshIo, ObjQuadsAreTriangulatedAndInwardCubeIsFlipped) {
    // Unit cube, quads wound clockwise seen from outside (inward normals); mixed-case extension.
    const std::string path = write_temp("inward.OBJ",
                                        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                        "f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n");
    const TriMesh m = load_closed_mesh(path);
    EXPECT_EQ(m.triangles.size(), 12u);
    EXPECT_DOUBLE_EQ(tridex::signed_volume(m), 1.0);
}

TEST(MeshIo, OffWithCommentLinesLoads) {
    // The OFF format allows '#' comments anywhere; OpenMesh's reader does not, so they are stripped first.
    const std::string path = write_temp("commented.off",
                                        "OFF\n# a tetrahedron\n4 4 0  # counts\n0 0 0\n1 0 0 # x\n0 1 0\n0 0 1\n"
                                        "# faces\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    const TriMesh m = load_closed_mesh(path);
    EXPECT_EQ(m.triangles.size(), 4u);
    EXPECT_DOUBLE_EQ(tridex::signed_volume(m), 1.0 / 6.0);
}

TEST(MeshIo, ObjRelativeIndicesAndAsciiStlLoad) {
    const std::string obj = write_temp("tet.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf -4 -2 -3\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    EXPECT_DOUBLE_EQ(tridex::signed_volume(load_closed_mesh(obj)), 1.0 / 6.0);
    std::ostringstream stl;
    stl << "solid tet\n";
    const double v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (const auto& t : f) {
        stl << "facet normal 0 0 0\nouter loop\n";
        for (int k : t) stl << "vertex " << v[k][0] << " " << v[k][1] << " " << v[k][2] << "\n";
        stl << "endloop\nendfacet\n";
    }
    stl << "endsolid tet\n";
    const TriMesh m = load_closed_mesh(write_temp("tet.stl", stl.str()));
    EXPECT_EQ(m.positions.size(), 4u);
    EXPECT_DOUBLE_EQ(tridex::signed_volume(m), 1.0 / 6.0);
}

TEST(MeshIo, RefusalReasons) {
    auto expect = [](const std::string& path, const std::string& tail) {
        const std::string msg = refusal(path);
        EXPECT_EQ(msg, path + ": " + tail);
    };
    expect(write_temp("a.xyz", "x"), "unknown mesh file extension '.xyz' (expected .off, .obj, .ply or .stl)");
    const std::string missing = (fs::path(testing::TempDir()) / "no_such_mesh.off").string();
    expect(missing, "no such file");
    expect(write_temp("short.off", "OFF\n100 1 0\n0 0 0\n"),
           "OFF header claims 100 vertices and 1 faces, impossible in a file of 18 bytes");
    expect(write_temp("words.off", "OFF\nmany 1 0\n"), "OFF header: vertex count 'many' is not a non-negative integer");
    {  // a text coordinate that is not a finite number, named with its line
        const std::string p = write_temp("nan.off", std::string("OFF\n4 4 0\n0 0 0\n1 0 0\nnan 1 0\n0 0 1\n") + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
        EXPECT_EQ(refusal(p), p + ":5: vertex 2 coordinate 'nan' is not a finite number");
    }
    {  // a binary STL facet with a NaN vertex coordinate
        std::string stl(84 + 50 * 4, '\0');
        stl[80] = 4;
        const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
        for (int t = 0; t < 4; ++t)
            for (int k = 0; k < 3; ++k) {
                float p[3] = {v[f[t][k]][0], v[f[t][k]][1], v[f[t][k]][2]};
                if (f[t][k] == 3) p[2] = std::nanf("");
                std::memcpy(&stl[84 + 50 * t + 12 + 12 * k], p, sizeof p);
            }
        expect(write_temp("nan.stl", stl), "facet 1 has a non-finite vertex coordinate");
    }
    {  // a binary PLY vertex with an infinite coordinate reaches the loader's own check
        std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
        const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, INFINITY}};
        ply.append(reinterpret_cast<const char*>(v), sizeof v);
        const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
        for (const auto& t : f) {
            ply.push_back(3);
            ply.append(reinterpret_cast<const char*>(t), sizeof t);
        }
        expect(write_temp("inf.ply", ply), "vertex 3 has a non-finite coordinate");
    }
    // A tetrahedron missing one face: 3 boundary edges.
    expect(write_temp("open.off", std::string("OFF\n4 3 0\n") + kTetVerts + "3 0 2 1\n3 0 1 3\n3 0 3 2\n"),
           "mesh is not closed: 3 boundary edges");
    // One face wound the wrong way: its 3 edges are each used twice in one direction.
    expect(write_temp("twisted.off", std::string("OFF\n4 4 0\n") + kTetVerts + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 3 2\n"),
           "mesh is not consistently oriented: 3 edges are used twice in the same direction");
    // Two tetrahedra sharing the edge 0-1: that edge has 4 triangles.
    expect(write_temp("bowtie.off", std::string("OFF\n6 8 0\n") + kTetVerts + "0 -1 0\n0 0 -1\n" +
                                        "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 0 4 5\n3 0 1 4\n3 0 5 1\n3 1 5 4\n"),
           "mesh is not a 2-manifold: 1 non-manifold edges (used by 3 or more triangles)");
    // Only degenerate triangles: nothing left after dropping them.
    expect(write_temp("flat.off", std::string("OFF\n4 2 0\n") + kTetVerts + "3 0 1 1\n3 2 2 2\n"), "no triangles");
    // PLY whose header claims more vertices than the body holds.
    expect(write_temp("huge.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                                  "property float y\nproperty float z\nend_header\n"),
           "PLY header declares more elements than a file of 124 bytes can hold");
    // Binary STL whose facet count disagrees with the size.
    std::string stl(84, '\0');
    stl[80] = 10;
    expect(write_temp("short.stl", stl), "binary STL header declares 10 facets (584 bytes) but the file has 84 bytes");
}
