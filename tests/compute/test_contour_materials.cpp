// Tests of painted materials through contouring: every vertex takes the material of its nearest generating
// edge crossing (a painted spot on a box face, a unioned bump), per-tile materials equal the whole mesh's,
// a paint-only stroke moves no vertex but gives the painted tiles new versions, PLY carries the materials.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/mesh/mesh_export.hpp"
#include "compute/tools/sweep.hpp"
#include "core/error.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;

constexpr int kCells = 48;
const Vec3 kBoxLo(8.3, 8.3, 8.3), kBoxHi(39.6, 39.6, 31.6);  // grid units; top face z = 31.6
constexpr double kSpotR = 5.0;                                // paint ball radius, cells
const Vec3 kSpotA(19.0, 24.0, 31.6), kSpotB(29.0, 24.0, 31.6);  // the spot's centre line, grid units
const Vec3 kBump(14.0, 34.0, 32.6);                           // union ball centre, grid units
constexpr double kBumpR = 3.5;

TriDexel box_model() {
    TriDexel m = empty_model(cube_lattice(kCells));
    fill_rays(m, [](int a, int u, int v) { return box_chord(kBoxLo, kBoxHi, a, u, v); });
    return m;
}

/// A ball sweep from a to b (grid units) with `op` and `material`.
Sweep ball_sweep(const Lattice& l, ToolOp op, const Vec3& a, const Vec3& b, double r_cells, std::uint8_t material) {
    Sweep s;
    s.op = op;
    s.tool = SweepTool{ToolKind::kBall, r_cells * l.cell_m, 0.0};
    s.path_m = Segment{l.to_world(a), l.to_world(b)};
    s.material = material;
    return s;
}

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 d = b - a;
    const double t = std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0);
    return glm::length(p - (a + t * d));
}

/// Per tile: the tile mesh's materials (empty tiles included, as empty lists).
std::vector<std::vector<std::uint8_t>> tile_materials(const Contourer& c) {
    std::vector<std::vector<std::uint8_t>> out(c.tile_count());
    for (std::size_t t = 0; t < c.tile_count(); ++t) (void)c.tile_mesh(t, out[t]);
    return out;
}

TEST(ContourMaterials, PaintedSpotAndUnionBumpGiveVertexMaterials) {
    TriDexel model = box_model();
    Contourer c(model);
    c.update(model);
    const TriMesh plain = c.mesh();
    const std::vector<std::uint8_t> plain_mat = c.mesh_materials();
    ASSERT_EQ(plain_mat.size(), plain.positions.size());
    EXPECT_EQ(std::count(plain_mat.begin(), plain_mat.end(), 0), static_cast<std::ptrdiff_t>(plain_mat.size()));

    const BooleanStats painted = apply_sweep(model, ball_sweep(model.lattice, ToolOp::kPaint, kSpotA, kSpotB, kSpotR, 2));
    EXPECT_GT(painted.rays_changed, 0u);
    c.update(model);
    const TriMesh m = c.mesh();
    const std::vector<std::uint8_t> mat = c.mesh_materials();
    ASSERT_EQ(mat.size(), m.positions.size());
    EXPECT_EQ(m.positions, plain.positions) << "paint moved a vertex";
    EXPECT_EQ(m.triangles, plain.triangles) << "paint changed the connectivity";
    std::size_t near = 0, far = 0;
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
        const double d = distance_to_segment(model.lattice.to_grid(m.positions[v]), kSpotA, kSpotB);
        if (d <= kSpotR - 1.0) {
            ++near;
            EXPECT_EQ(mat[v], 2) << "vertex " << v << " at " << d << " cells from the spot's line";
        } else if (d > kSpotR + 1.5) {
            ++far;
            EXPECT_EQ(mat[v], 0) << "vertex " << v << " at " << d << " cells from the spot's line";
        }
    }
    EXPECT_GT(near, 100u);
    EXPECT_GT(far, 1000u);

    // A bump unioned as material 3: every vertex above the top face is on it.
    apply_sweep(model, ball_sweep(model.lattice, ToolOp::kUnion, kBump, kBump + Vec3(0.5, 0.0, 0.0), kBumpR, 3));
    c.update(model);
    const TriMesh b = c.mesh();
    const std::vector<std::uint8_t> bmat = c.mesh_materials();
    ASSERT_EQ(bmat.size(), b.positions.size());
    std::size_t bump = 0, still_painted = 0;
    for (std::size_t v = 0; v < b.positions.size(); ++v) {
        const Vec3 g = model.lattice.to_grid(b.positions[v]);
        if (g.z > kBoxHi.z + 1.0) {
            ++bump;
            EXPECT_EQ(bmat[v], 3) << "bump vertex " << v << " at z " << g.z;
        }
        if (distance_to_segment(g, kSpotA, kSpotB) <= kSpotR - 1.0) {
            ++still_painted;
            EXPECT_EQ(bmat[v], 2);
        }
    }
    EXPECT_GT(bump, 20u);
    EXPECT_EQ(still_painted, near);

    // Per tile: each tile vertex has the material of the same (bit-identical) vertex of the whole mesh.
    std::map<std::array<double, 3>, std::uint8_t> by_position;
    for (std::size_t v = 0; v < b.positions.size(); ++v) {
        const std::array<double, 3> key{b.positions[v].x, b.positions[v].y, b.positions[v].z};
        const auto [it, fresh] = by_position.emplace(key, bmat[v]);
        if (!fresh) {
            EXPECT_EQ(it->second, bmat[v]) << "two vertices at one position with different materials";
        }
    }
    TileSurfaceCache cache;
    cache.refresh(c);
    std::size_t checked = 0;
    for (const TileSurface& s : cache.tiles()) {
        ASSERT_EQ(s.materials.size(), s.mesh.positions.size()) << "tile " << s.id;
        std::vector<std::uint8_t> direct;
        const TriMesh tm = c.tile_mesh(s.id, direct);
        EXPECT_EQ(direct, s.materials);
        EXPECT_EQ(tm.positions, s.mesh.positions);
        for (std::size_t v = 0; v < s.mesh.positions.size(); ++v) {
            const Vec3& p = s.mesh.positions[v];
            const auto it = by_position.find({p.x, p.y, p.z});
            ASSERT_NE(it, by_position.end()) << "tile " << s.id << " vertex " << v << " not in mesh()";
            EXPECT_EQ(it->second, s.materials[v]) << "tile " << s.id << " vertex " << v;
            ++checked;
        }
    }
    EXPECT_GE(checked, b.positions.size());  // shared vertices are counted once per tile using them
}

TEST(ContourMaterials, PaintOnlyStrokeBumpsExactlyThePaintedTilesVersions) {
    TriDexel model = box_model();
    Contourer c(model);
    c.update(model);
    apply_sweep(model, ball_sweep(model.lattice, ToolOp::kPaint, kSpotA, kSpotB, kSpotR, 2));
    c.update(model);
    const TriMesh before = c.mesh();
    std::vector<std::uint64_t> versions(c.tile_count());
    for (std::size_t t = 0; t < c.tile_count(); ++t) versions[t] = c.tile_version(t);
    const auto mats_before = tile_materials(c);

    // A second spot, partly over the first (repainting it), crossing tile borders (x = 16, 32).
    const Vec3 a(12.0, 20.0, 31.6), bb(34.0, 20.0, 31.6);
    apply_sweep(model, ball_sweep(model.lattice, ToolOp::kPaint, a, bb, 4.0, 5));
    const std::size_t redone = c.update(model);
    EXPECT_GT(redone, 0u);
    const TriMesh after = c.mesh();
    EXPECT_EQ(after.positions, before.positions);
    EXPECT_EQ(after.triangles, before.triangles);
    const auto mats_after = tile_materials(c);
    std::vector<std::uint64_t> versions_after(c.tile_count());
    std::size_t bumped = 0, far_kept = 0;
    for (std::size_t t = 0; t < c.tile_count(); ++t) {
        versions_after[t] = c.tile_version(t);
        if (mats_after[t] != mats_before[t]) {
            ++bumped;
            EXPECT_NE(versions_after[t], versions[t]) << "tile " << t << ": materials changed, version kept";
        }
        // A tile all of whose vertices are well away from the stroke keeps its version. (A tile may get a new
        // version with unchanged tile_mesh materials: a vertex it owns but only neighbours use was repainted.)
        const TriMesh tm = c.tile_mesh(t);
        bool away = !tm.positions.empty();
        for (const Vec3& p : tm.positions)
            if (distance_to_segment(model.lattice.to_grid(p), a, bb) <= 4.0 + 3.0) away = false;
        if (away) {
            ++far_kept;
            EXPECT_EQ(versions_after[t], versions[t]) << "tile " << t << ": far from the stroke, version bumped";
        }
    }
    EXPECT_GE(bumped, 3u);  // the stroke spans three tiles along x
    EXPECT_GT(far_kept, 0u);
    // Repainting with the same material changes no ray: no version moves.
    const BooleanStats again = apply_sweep(model, ball_sweep(model.lattice, ToolOp::kPaint, a, bb, 4.0, 5));
    EXPECT_EQ(again.rays_changed, 0u);
    c.update(model);
    for (std::size_t t = 0; t < c.tile_count(); ++t) EXPECT_EQ(c.tile_version(t), versions_after[t]) << "tile " << t;
    EXPECT_EQ(tile_materials(c), mats_after);
}

TEST(ContourMaterials, PlyCarriesPerVertexMaterials) {
    TriDexel model = box_model();
    Contourer c(model);
    c.update(model);
    apply_sweep(model, ball_sweep(model.lattice, ToolOp::kPaint, kSpotA, kSpotB, kSpotR, 2));
    c.update(model);
    const TriMesh m = c.mesh();
    const std::vector<std::uint8_t> mat = c.mesh_materials();
    const auto dir = std::filesystem::temp_directory_path() / "tridex_contour_materials";
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "painted.ply").string();
    write_ply(path, m, mat);
    std::ifstream f(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const std::string end = "end_header\n";
    const std::size_t body = bytes.find(end);
    ASSERT_NE(body, std::string::npos);
    const std::string header = bytes.substr(0, body);
    EXPECT_NE(header.find("property float z\nproperty uchar material\nelement face"), std::string::npos) << header;
    const std::size_t start = body + end.size();
    ASSERT_EQ(bytes.size(), start + m.positions.size() * 13 + m.triangles.size() * 13);
    for (std::size_t v = 0; v < m.positions.size(); ++v)
        ASSERT_EQ(static_cast<std::uint8_t>(bytes[start + v * 13 + 12]), mat[v]) << "vertex " << v;
    // Without materials the file is as before; a wrong count throws.
    write_ply(path, m);
    EXPECT_EQ(std::filesystem::file_size(path), start - std::string("property uchar material\n").size() +
                                                     m.positions.size() * 12 + m.triangles.size() * 13);
    const std::vector<std::uint8_t> short_list(m.positions.size() - 1, 0);
    EXPECT_THROW(write_ply(path, m, short_list), Error);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tridex::compute
