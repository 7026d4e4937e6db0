// Tests of the Contourer's per-tile vertex normals (Contourer::tile_mesh with normals): each tile's are the whole
// surface's, bit for bit, so neighbouring tiles shade a shared vertex alike; a tile's version changes whenever its
// normals do; TileSurfaceCache carries them.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/tools/boolean.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;
using Key = std::array<double, 3>;

Key key_of(const Vec3& p) { return {p.x, p.y, p.z}; }

/// The whole mesh's area-weighted vertex normals by vertex position (positions that occur twice are left out).
std::map<Key, Vec3> whole_normals(const Contourer& c) {
    const TriMesh whole = c.mesh();
    const std::vector<Vec3> n = vertex_normals(whole);
    std::map<Key, Vec3> out;
    std::map<Key, int> seen;
    for (std::size_t v = 0; v < whole.positions.size(); ++v) {
        out[key_of(whole.positions[v])] = n[v];
        ++seen[key_of(whole.positions[v])];
    }
    for (const auto& [k, count] : seen)
        if (count > 1) out.erase(k);
    return out;
}

TriDexel sphere_model(int cells) {
    TriDexel model = empty_model(cube_lattice(cells));
    const Vec3 c(0.5 * cells + 0.31, 0.5 * cells - 0.22, 0.5 * cells + 0.13);
    fill_rays(model, [&](int a, int u, int v) { return sphere_chord(c, 0.38 * cells, a, u, v); });
    return model;
}

// A sphere across 4 x 4 x 4 tiles, carved: every tile's normals are the whole mesh's (core vertex_normals) at the
// same vertices, bit for bit. A tile's own normals (vertex_normals of its mesh alone) differ at its border.
TEST(ContourTileNormals, EachTilesNormalsAreTheWholeSurfacesBitForBit) {
    TriDexel model = sphere_model(64);
    Contourer contourer(model);
    contourer.update(model);
    const Lattice& l = model.lattice;
    subtract_capsule(model, Segment{l.to_world(Vec3(50.0, 30.0, 31.0)), l.to_world(Vec3(58.0, 34.0, 33.0))},
                     5.0 * l.cell_m);
    contourer.update(model);
    const std::map<Key, Vec3> whole = whole_normals(contourer);
    std::size_t checked = 0, own_differ = 0;
    for (std::size_t t = 0; t < contourer.tile_count(); ++t) {
        std::vector<std::uint8_t> materials;
        std::vector<Vec3> normals;
        const TriMesh m = contourer.tile_mesh(t, materials, normals);
        ASSERT_EQ(normals.size(), m.positions.size()) << t;
        const std::vector<Vec3> own = vertex_normals(m);
        for (std::size_t v = 0; v < m.positions.size(); ++v) {
            const auto it = whole.find(key_of(m.positions[v]));
            if (it == whole.end()) continue;
            EXPECT_EQ(normals[v], it->second) << "tile " << t << " vertex " << v;
            ++checked;
            own_differ += glm::length(own[v] - it->second) > 1e-6 ? 1 : 0;
        }
    }
    EXPECT_GT(checked, 1000u);
    EXPECT_GT(own_differ, 100u);  // what a tile's mesh alone gives at its border
}

// Small carves at random places on the sphere, each contoured at once: a tile whose version stayed has the same
// mesh and the same normals as before, so a renderer that re-uploads by version never keeps a stale normal. Some
// tiles get a new version for their normals alone (a neighbour's triangles around a vertex they share changed).
TEST(ContourTileNormals, AVersionChangesWheneverTheTilesNormalsDo) {
    TriDexel model = sphere_model(64);
    Contourer contourer(model);
    contourer.update(model);
    const Lattice& l = model.lattice;
    const auto read = [&](std::vector<TriMesh>& meshes, std::vector<std::vector<Vec3>>& normals) {
        meshes.assign(contourer.tile_count(), TriMesh{});
        normals.assign(contourer.tile_count(), {});
        for (std::size_t t = 0; t < contourer.tile_count(); ++t) {
            std::vector<std::uint8_t> materials;
            meshes[t] = contourer.tile_mesh(t, materials, normals[t]);
        }
    };
    std::vector<TriMesh> meshes;
    std::vector<std::vector<Vec3>> normals;
    read(meshes, normals);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const Vec3 centre(32.31, 31.78, 32.13);
    std::size_t normals_only = 0;
    for (int cut = 0; cut < 24; ++cut) {
        Vec3 d(unit(rng), unit(rng), unit(rng));
        d = glm::normalize(d);
        const Vec3 at = centre + 24.3 * d;  // on the sphere (radius 24.32 cells)
        const Vec3 along(unit(rng), unit(rng), unit(rng));
        subtract_capsule(model, Segment{l.to_world(at), l.to_world(at + 2.0 * along)}, 1.6 * l.cell_m);
        std::vector<std::uint64_t> versions(contourer.tile_count());
        for (std::size_t t = 0; t < versions.size(); ++t) versions[t] = contourer.tile_version(t);
        contourer.update(model);
        std::vector<TriMesh> meshes_now;
        std::vector<std::vector<Vec3>> normals_now;
        read(meshes_now, normals_now);
        for (std::size_t t = 0; t < versions.size(); ++t) {
            const bool same_mesh =
                meshes_now[t].positions == meshes[t].positions && meshes_now[t].triangles == meshes[t].triangles;
            const bool same_normals = normals_now[t] == normals[t];
            if (contourer.tile_version(t) == versions[t]) {
                EXPECT_TRUE(same_mesh) << "cut " << cut << " tile " << t;
                EXPECT_TRUE(same_normals) << "cut " << cut << " tile " << t;
            } else if (same_mesh && !same_normals) {
                ++normals_only;
            }
        }
        meshes = std::move(meshes_now);
        normals = std::move(normals_now);
    }
    EXPECT_GT(normals_only, 0u);
}

// Small cuts near tile corners: a moved vertex reshapes triangles of tiles the update did not re-contour, and the
// other vertices of those triangles may be held by a third tile; it too gets a new version. (A sequence that left
// such a tile with a stale normal at cut 140 before that rule.)
TEST(ContourTileNormals, CutsNearTileCornersGiveEveryTileWhoseNormalsChangedANewVersion) {
    TriDexel model = sphere_model(64);
    Contourer contourer(model);
    contourer.update(model);
    const Lattice& l = model.lattice;
    const Vec3 centre(32.31, 31.78, 32.13);
    std::vector<TriMesh> meshes(contourer.tile_count());
    std::vector<std::vector<Vec3>> normals(contourer.tile_count());
    const auto read = [&](std::size_t t, TriMesh& m, std::vector<Vec3>& n) {
        std::vector<std::uint8_t> materials;
        m = contourer.tile_mesh(t, materials, n);
    };
    for (std::size_t t = 0; t < meshes.size(); ++t) read(t, meshes[t], normals[t]);
    std::mt19937 rng(21);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), radius(0.4, 2.0);
    std::size_t stale = 0;
    for (int cut = 0; cut < 150; ++cut) {
        const Vec3 d = glm::normalize(Vec3(unit(rng), unit(rng), unit(rng)));
        Vec3 at = centre + 24.3 * d + 1.5 * Vec3(unit(rng), unit(rng), unit(rng));
        for (int a = 0; a < 3; ++a) at[a] = 16.0 * std::round(at[a] / 16.0) + 2.5 * unit(rng);  // near a corner
        const Vec3 along(unit(rng), unit(rng), unit(rng));
        subtract_capsule(model, Segment{l.to_world(at), l.to_world(at + 2.0 * along)}, radius(rng) * l.cell_m);
        std::vector<std::uint64_t> versions(meshes.size());
        for (std::size_t t = 0; t < versions.size(); ++t) versions[t] = contourer.tile_version(t);
        contourer.update(model);
        for (std::size_t t = 0; t < meshes.size(); ++t) {
            TriMesh m;
            std::vector<Vec3> n;
            read(t, m, n);
            if (contourer.tile_version(t) == versions[t]) {
                const bool same =
                    m.positions == meshes[t].positions && m.triangles == meshes[t].triangles && n == normals[t];
                EXPECT_TRUE(same) << "cut " << cut << " tile " << t;
                stale += same ? 0 : 1;
            }
            meshes[t] = std::move(m);
            normals[t] = std::move(n);
        }
    }
    EXPECT_EQ(stale, 0u);
}

// TileSurfaceCache::refresh keeps each tile's normals with its mesh, as the Contourer gives them.
TEST(ContourTileNormals, TheCacheCarriesEachTilesNormals) {
    TriDexel model = sphere_model(48);
    Contourer contourer(model);
    contourer.update(model);
    TileSurfaceCache cache;
    cache.refresh(contourer);
    ASSERT_FALSE(cache.tiles().empty());
    for (const TileSurface& s : cache.tiles()) {
        std::vector<std::uint8_t> materials;
        std::vector<Vec3> normals;
        const TriMesh m = contourer.tile_mesh(static_cast<std::size_t>(s.id), materials, normals);
        ASSERT_EQ(s.normals.size(), s.mesh.positions.size()) << s.id;
        EXPECT_EQ(s.mesh.positions, m.positions) << s.id;
        EXPECT_EQ(s.normals, normals) << s.id;
    }
}

}  // namespace
}  // namespace tridex::compute
