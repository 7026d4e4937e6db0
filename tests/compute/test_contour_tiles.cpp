// Tests of compute/contour/contour_tiles (TileSurfaceCache) and the Contourer's per-tile accessors: the tiles'
// triangles together are exactly mesh()'s triangles, versions change exactly where the surface changed,
// refresh() rebuilds only those tiles and drops tiles that became empty.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/sorted_ids.hpp"
#include "compute/tools/boolean.hpp"
#include "core/error.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;
using Triple = std::array<double, 9>;

/// The triangles of `m` as sorted position triples (vertex order kept: orientation matters).
std::vector<Triple> triples(const TriMesh& m) {
    std::vector<Triple> out;
    out.reserve(m.triangles.size());
    for (const auto& t : m.triangles) {
        Triple x{};
        for (int v = 0; v < 3; ++v)
            for (int c = 0; c < 3; ++c) x[3 * v + c] = m.positions[t[v]][c];
        out.push_back(x);
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<Triple> union_of_tiles(const TileSurfaceCache& cache) {
    std::vector<Triple> all;
    for (const TileSurface& s : cache.tiles()) {
        const std::vector<Triple> t = triples(s.mesh);
        all.insert(all.end(), t.begin(), t.end());
    }
    std::sort(all.begin(), all.end());
    return all;
}

/// Every tile is non-empty, compact (each vertex used), has the box of its positions, ids ascend.
void expect_well_formed(const TileSurfaceCache& cache, const Contourer& c) {
    for (std::size_t i = 0; i < cache.tiles().size(); ++i) {
        const TileSurface& s = cache.tiles()[i];
        if (i > 0) {
            EXPECT_LT(cache.tiles()[i - 1].id, s.id);
        }
        EXPECT_FALSE(s.mesh.triangles.empty()) << s.id;
        EXPECT_EQ(s.version, c.tile_version(s.id));
        EXPECT_EQ(c.tile_triangle_count(s.id), s.mesh.triangles.size()) << s.id;  // the count follows every update
        std::vector<bool> used(s.mesh.positions.size(), false);
        for (const auto& t : s.mesh.triangles)
            for (std::uint32_t v : t) used[v] = true;
        EXPECT_EQ(std::count(used.begin(), used.end(), false), 0) << s.id;
        EXPECT_EQ(s.bounds_m.lo, s.mesh.bounds().lo);
        EXPECT_EQ(s.bounds_m.hi, s.mesh.bounds().hi);
    }
    std::size_t nonempty = 0;
    for (std::size_t t = 0; t < c.tile_count(); ++t) nonempty += c.tile_triangle_count(t) > 0 ? 1 : 0;
    EXPECT_EQ(cache.tiles().size(), nonempty);
}

std::vector<std::array<int, 3>> tile_coords(const TriDexel& m) {
    std::vector<std::array<int, 3>> out(m.tiles.count());
    for (int z = 0; z < m.tiles.tiles[2]; ++z)
        for (int y = 0; y < m.tiles.tiles[1]; ++y)
            for (int x = 0; x < m.tiles.tiles[0]; ++x) out[m.tiles.index(x, y, z)] = {x, y, z};
    return out;
}

struct Snapshot {
    std::vector<std::uint64_t> versions;
    std::vector<TriMesh> meshes;
    std::vector<std::vector<Vec3>> normals;  // the whole surface's at each tile's vertices
};

Snapshot snapshot(const Contourer& c) {
    Snapshot s;
    for (std::size_t t = 0; t < c.tile_count(); ++t) {
        s.versions.push_back(c.tile_version(t));
        std::vector<std::uint8_t> materials;
        s.normals.emplace_back();
        s.meshes.push_back(c.tile_mesh(t, materials, s.normals.back()));
    }
    return s;
}

bool same_mesh(const TriMesh& a, const TriMesh& b) {
    return a.positions == b.positions && a.triangles == b.triangles;
}

TEST(ContourTiles, UnionOfTilesIsTheMeshBeforeAndAfterACapsuleCarve) {
    const Lattice l = cube_lattice(80);  // 5 x 5 x 5 tiles
    TriDexel model = empty_model(l);
    const Vec3 c(40.3, 39.6, 40.2);
    fill_rays(model, [&](int a, int u, int v) { return sphere_chord(c, 30.7, a, u, v); });
    Contourer contourer(model);
    contourer.update(model);

    TileSurfaceCache cache;
    const std::size_t first = cache.refresh(contourer);
    EXPECT_EQ(first, cache.tiles().size());
    EXPECT_GT(first, 20u);
    EXPECT_LT(first, 125u);  // the centre tile and the corners hold no surface
    expect_well_formed(cache, contourer);
    EXPECT_EQ(union_of_tiles(cache), triples(contourer.mesh()));
    EXPECT_EQ(cache.triangle_count(), contourer.mesh().triangles.size());
    EXPECT_EQ(cache.refresh(contourer), 0u);  // nothing changed

    const Snapshot before = snapshot(contourer);
    std::vector<const Vec3*> data;
    for (const TileSurface& s : cache.tiles()) data.push_back(s.mesh.positions.data());
    std::vector<std::uint64_t> ids_before;
    for (const TileSurface& s : cache.tiles()) ids_before.push_back(s.id);

    // A ball of radius 6 cells swept along x through the sphere's surface near +x.
    const Segment seg{l.to_world(Vec3(62.0, 45.5, 41.3)), l.to_world(Vec3(75.0, 47.5, 43.1))};
    subtract_capsule(model, seg, 6.0 * l.cell_m);
    std::vector<std::uint8_t> dirty = model.tiles.dirty;
    ASSERT_GT(std::count_if(dirty.begin(), dirty.end(), [](std::uint8_t d) { return d != 0; }), 0);
    contourer.update(model);
    const Snapshot after = snapshot(contourer);

    // Which tiles' surfaces really changed, and which tiles could be affected (dirty, or a neighbour of a
    // dirty tile: the only tiles that can borrow its vertices).
    const auto coords = tile_coords(model);
    std::set<std::size_t> changed_mesh, changed_version;
    for (std::size_t t = 0; t < contourer.tile_count(); ++t) {
        if (!same_mesh(before.meshes[t], after.meshes[t]) || before.normals[t] != after.normals[t])
            changed_mesh.insert(t);
        if (before.versions[t] != after.versions[t]) changed_version.insert(t);
    }
    EXPECT_FALSE(changed_mesh.empty());
    // A version changes whenever the tile's mesh (own triangles, own or borrowed vertex positions) or its vertices'
    // normals (a neighbour's triangles around a shared vertex) changed; a tile whose neighbour's triangles near it
    // changed may get one with its normals the same, but here none does.
    EXPECT_TRUE(
        std::includes(changed_version.begin(), changed_version.end(), changed_mesh.begin(), changed_mesh.end()));
    EXPECT_EQ(changed_version, changed_mesh);
    for (std::size_t t : changed_version) {
        bool near_dirty = false;
        for (std::size_t d = 0; d < dirty.size(); ++d)
            if (dirty[d]) {
                bool adjacent = true;
                for (int a = 0; a < 3; ++a) adjacent = adjacent && std::abs(coords[t][a] - coords[d][a]) <= 1;
                near_dirty = near_dirty || adjacent;
            }
        EXPECT_TRUE(near_dirty) << t;
    }

    // refresh() rebuilds exactly the changed non-empty tiles and keeps the others' meshes in place.
    std::size_t expected = 0;
    for (std::size_t t : changed_version) expected += contourer.tile_triangle_count(t) > 0 ? 1 : 0;
    EXPECT_EQ(cache.refresh(contourer), expected);
    expect_well_formed(cache, contourer);
    EXPECT_EQ(union_of_tiles(cache), triples(contourer.mesh()));
    std::size_t kept = 0;
    for (const TileSurface& s : cache.tiles()) {
        const auto it = std::find(ids_before.begin(), ids_before.end(), s.id);
        if (it == ids_before.end() || changed_version.count(s.id) != 0) continue;
        EXPECT_EQ(s.mesh.positions.data(), data[static_cast<std::size_t>(it - ids_before.begin())]) << s.id;
        ++kept;
    }
    EXPECT_EQ(kept + expected, cache.tiles().size());
    EXPECT_GT(kept, expected);
}

TEST(ContourTiles, RecontouringWithoutChangeKeepsVersions) {
    const Lattice l = cube_lattice(64);
    TriDexel model = empty_model(l);
    fill_rays(model, [&](int a, int u, int v) { return sphere_chord(Vec3(31.7, 32.2, 32.4), 20.3, a, u, v); });
    Contourer contourer(model);
    contourer.update(model);
    TileSurfaceCache cache;
    cache.refresh(contourer);
    const Snapshot before = snapshot(contourer);
    // Dirty everything without changing the model: every tile is redone, none changes.
    std::fill(model.tiles.dirty.begin(), model.tiles.dirty.end(), std::uint8_t{1});
    EXPECT_EQ(contourer.update(model), 64u);
    EXPECT_EQ(snapshot(contourer).versions, before.versions);
    EXPECT_EQ(cache.refresh(contourer), 0u);
}

TEST(ContourTiles, TilesThatBecomeEmptyAreDropped) {
    // Two small balls in opposite corner tiles; carving one away entirely leaves only the other's tiles.
    const Lattice l = cube_lattice(64);  // 4 x 4 x 4 tiles
    TriDexel model = empty_model(l);
    const Vec3 a(8.4, 8.3, 8.6), b(55.2, 55.7, 55.1);
    fill_rays(model, [&](int ax, int u, int v) {
        std::vector<Interval> s = sphere_chord(a, 4.2, ax, u, v);
        const std::vector<Interval> t = sphere_chord(b, 4.2, ax, u, v);
        s.insert(s.end(), t.begin(), t.end());
        return s;
    });
    Contourer contourer(model);
    contourer.update(model);
    TileSurfaceCache cache;
    EXPECT_EQ(cache.refresh(contourer), 2u);
    ASSERT_EQ(cache.tiles().size(), 2u);
    EXPECT_EQ(cache.tiles()[0].id, model.tiles.index(0, 0, 0));
    EXPECT_EQ(cache.tiles()[1].id, model.tiles.index(3, 3, 3));
    const TriMesh kept_before = cache.tiles()[1].mesh;

    subtract_capsule(model, Segment{l.to_world(a), l.to_world(a)}, 6.0 * l.cell_m);
    contourer.update(model);
    EXPECT_EQ(contourer.tile_triangle_count(model.tiles.index(0, 0, 0)), 0u);
    EXPECT_EQ(cache.refresh(contourer), 0u);  // nothing to rebuild, one tile dropped
    ASSERT_EQ(cache.tiles().size(), 1u);
    EXPECT_EQ(cache.tiles()[0].id, model.tiles.index(3, 3, 3));
    EXPECT_TRUE(same_mesh(cache.tiles()[0].mesh, kept_before));
    EXPECT_EQ(union_of_tiles(cache), triples(contourer.mesh()));
}

TEST(ContourTiles, TileAccessorsRejectOutOfRangeTiles) {
    const Lattice l = cube_lattice(32);
    TriDexel model = empty_model(l);
    Contourer contourer(model);
    contourer.update(model);
    EXPECT_EQ(contourer.tile_count(), 8u);
    EXPECT_THROW(contourer.tile_version(8), Error);
    EXPECT_THROW(contourer.tile_mesh(8), Error);
    EXPECT_THROW(contourer.tile_triangle_count(99), Error);
    TileSurfaceCache cache;
    EXPECT_EQ(cache.refresh(contourer), 0u);  // an empty model has no tiles
    EXPECT_TRUE(cache.tiles().empty());
}

TEST(SortedIds, MergeIdsKeepsTheUnionAscendingWithoutRepeats) {
    std::vector<std::uint64_t> into{2, 5, 9};
    merge_ids(into, {1, 5, 7, 12});
    EXPECT_EQ(into, (std::vector<std::uint64_t>{1, 2, 5, 7, 9, 12}));
    merge_ids(into, {});
    EXPECT_EQ(into.size(), 6u);
    std::vector<std::uint64_t> empty;
    merge_ids(empty, {3});
    EXPECT_EQ(empty, std::vector<std::uint64_t>{3});
}

}  // namespace
}  // namespace tridex::compute
