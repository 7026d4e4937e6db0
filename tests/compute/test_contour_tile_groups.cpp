// tests/compute/test_contour_tile_groups.cpp - levels of detail over groups of tiles: borders kept, mixes with tiles
// stay closed, errors bounded, flat faces collapse, dirty tiles rebuild their groups.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <array>
#include <map>
#include <set>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/surface_distance.hpp"
#include "compute/contour/tile_group_lod.hpp"
#include "compute/tools/boolean.hpp"
#include "compute/tools/sweep.hpp"
#include "core/error.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;
using Point = std::array<double, 3>;
using Edge = std::pair<Point, Point>;  // directed, by position

struct Built {
    TriDexel model;
    Contourer contourer;
    TileSurfaceCache cache;
};

Built build(int cells, const std::function<std::vector<Interval>(int, int, int)>& chord, int depth = 3,
            LodErrorMeasure measure = LodErrorMeasure::kEstimate) {
    TriDexel model = empty_model(cube_lattice(cells));
    fill_rays(model, chord);
    Contourer c(model);
    c.update(model);
    Built b{std::move(model), std::move(c), {}};
    TileLodOptions o;
    o.cell_m = b.model.lattice.cell_m;
    o.group_depth = depth;
    o.measure = measure;
    b.cache.enable_lod(o);
    b.cache.refresh(b.contourer);
    return b;
}

Built sphere(int cells, LodErrorMeasure measure = LodErrorMeasure::kEstimate) {
    const Vec3 centre(0.5 * cells + 0.31, 0.5 * cells - 0.17, 0.5 * cells + 0.07);
    return build(cells, [&, r = 0.38 * cells](int a, int u, int v) { return sphere_chord(centre, r, a, u, v); }, 3,
                 measure);
}

Built box(int cells) {
    const Vec3 lo(3.3, 4.4, 2.6), hi(cells - 3.7, cells - 2.2, cells - 4.1);
    return build(cells, [&](int a, int u, int v) { return box_chord(lo, hi, a, u, v); });
}

// Built once for the tests that only read them.
const Built& shared_sphere() {
    static const Built b = sphere(96);
    return b;
}
const Built& shared_box() {
    static const Built b = box(96);
    return b;
}

Point point(const Vec3& p) { return {p.x, p.y, p.z}; }

// Directed edges of `m` by position whose reverse `m` lacks: its open border.
std::set<Edge> open_edges(const std::vector<const TriMesh*>& meshes) {
    std::set<Edge> directed;
    for (const TriMesh* m : meshes)
        for (const auto& t : m->triangles)
            for (int k = 0; k < 3; ++k) directed.insert({point(m->positions[t[k]]), point(m->positions[t[(k + 1) % 3]])});
    std::set<Edge> open;
    for (const Edge& e : directed)
        if (!directed.count({e.second, e.first})) open.insert(e);
    return open;
}

const TileSurface* tile(const TileSurfaceCache& c, std::uint64_t id) {
    for (const TileSurface& t : c.tiles())
        if (t.id == id) return &t;
    return nullptr;
}
const TileGroupSurface* group(const TileSurfaceCache& c, std::uint64_t id) {
    for (const TileGroupSurface& g : c.groups())
        if (g.id == id) return &g;
    return nullptr;
}

// Every tile under group g (ids).
void tiles_under(const TileSurfaceCache& c, const TileGroupSurface& g, std::vector<std::uint64_t>& out) {
    for (const std::uint64_t ch : g.children) {
        if (g.depth == 1)
            out.push_back(ch);
        else
            tiles_under(c, *group(c, ch), out);
    }
}

// The whole surface welded by position: the given groups at the given levels (1-based), every other tile full.
TriMesh assemble(const TileSurfaceCache& c, const std::vector<std::pair<const TileGroupSurface*, std::size_t>>& drawn) {
    std::set<std::uint64_t> covered;
    std::vector<const TriMesh*> meshes;
    for (const auto& [g, level] : drawn) {
        std::vector<std::uint64_t> ids;
        tiles_under(c, *g, ids);
        covered.insert(ids.begin(), ids.end());
        meshes.push_back(&g->lods[level - 1].mesh);
    }
    for (const TileSurface& t : c.tiles())
        if (!covered.count(t.id)) meshes.push_back(&t.mesh);
    TriMesh out;
    std::map<Point, std::uint32_t> index;
    for (const TriMesh* m : meshes)
        for (const auto& t : m->triangles) {
            std::array<std::uint32_t, 3> w{};
            for (int k = 0; k < 3; ++k) {
                const auto [it, fresh] = index.try_emplace(point(m->positions[t[k]]), static_cast<std::uint32_t>(out.positions.size()));
                if (fresh) out.positions.push_back(m->positions[t[k]]);
                w[k] = it->second;
            }
            out.triangles.push_back(w);
        }
    return out;
}

TEST(TileGroupLod, GroupsCoverTheirTilesAndNameTheirParents) {
    const Built& b = shared_sphere();  // 6 tiles along each axis: depth-3 groups are clipped at the lattice's end
    const TileSurfaceCache& c = b.cache;
    ASSERT_FALSE(c.groups().empty());
    std::map<int, std::set<std::uint64_t>> tiles_at_depth;
    for (const TileGroupSurface& g : c.groups()) {
        EXPECT_FALSE(g.children.empty());
        EXPECT_TRUE(std::is_sorted(g.children.begin(), g.children.end()));
        std::vector<std::uint64_t> ids;
        tiles_under(c, g, ids);
        for (const std::uint64_t t : ids) {
            EXPECT_TRUE(tiles_at_depth[g.depth].insert(t).second) << "tile " << t << " in two depth-" << g.depth << " groups";
            ASSERT_NE(tile(c, t), nullptr);
            EXPECT_TRUE(g.bounds_m.contains(tile(c, t)->bounds_m.lo) && g.bounds_m.contains(tile(c, t)->bounds_m.hi));
        }
        if (g.depth < 3) {
            const TileGroupSurface* p = group(c, g.parent);
            ASSERT_NE(p, nullptr);
            EXPECT_EQ(p->depth, g.depth + 1);
            EXPECT_TRUE(std::count(p->children.begin(), p->children.end(), g.id));
        } else {
            EXPECT_EQ(g.parent, TileGroupSurface::kNone);
        }
    }
    for (int d = 1; d <= 3; ++d) EXPECT_EQ(tiles_at_depth[d].size(), c.tiles().size()) << "depth " << d;
}

TEST(TileGroupLod, LevelsKeepTheGroupsOuterBorderExactly) {
    for (const bool flat : {false, true}) {
        const Built& b = flat ? shared_box() : shared_sphere();
        const TileSurfaceCache& c = b.cache;
        std::size_t checked = 0;
        for (const TileGroupSurface& g : c.groups()) {
            std::vector<std::uint64_t> ids;
            tiles_under(c, g, ids);
            std::vector<const TriMesh*> full;
            for (const std::uint64_t t : ids) full.push_back(&tile(c, t)->mesh);
            // The children's union: the group's outer border only (inner tile borders pair up).
            const std::set<Edge> border = open_edges(full);
            for (const TileLodLevel& l : g.lods) {
                EXPECT_EQ(open_edges({&l.mesh}), border) << "flat " << flat << " group " << g.id;
                ++checked;
            }
        }
        EXPECT_GT(checked, 10u) << "flat " << flat;
    }
}

TEST(TileGroupLod, AnyGroupAmongFullTilesKeepsTheSurfaceClosed) {
    const Built& b = shared_sphere();
    const TileSurfaceCache& c = b.cache;
    // Each depth: every group with levels at its coarsest level at once, the other tiles full.
    for (int depth = 1; depth <= 3; ++depth) {
        std::vector<std::pair<const TileGroupSurface*, std::size_t>> drawn;
        for (const TileGroupSurface& g : c.groups())
            if (g.depth == depth && !g.lods.empty()) drawn.push_back({&g, g.lods.size()});
        ASSERT_FALSE(drawn.empty()) << "depth " << depth;
        SCOPED_TRACE(::testing::Message() << "depth " << depth);
        expect_closed_manifold(assemble(c, drawn));
    }
    // Groups of different depths side by side, finest levels.
    std::vector<std::pair<const TileGroupSurface*, std::size_t>> mixed;
    std::set<std::uint64_t> used;
    for (const TileGroupSurface& g : c.groups()) {
        if (g.lods.empty() || (g.coords[0] + g.coords[1] + g.depth) % 2 != 0) continue;
        std::vector<std::uint64_t> ids;
        tiles_under(c, g, ids);
        if (std::any_of(ids.begin(), ids.end(), [&](std::uint64_t t) { return used.count(t); })) continue;
        used.insert(ids.begin(), ids.end());
        mixed.push_back({&g, 1});
    }
    ASSERT_GT(mixed.size(), 1u);
    expect_closed_manifold(assemble(c, mixed));
}

// The largest distance between each group level and the full surface of the tiles under the group (samples 0.2
// cells apart on both), over its stored error_m, per level.
std::vector<double> group_level_ratios(const Built& b) {
    const double cell = b.model.lattice.cell_m;
    std::vector<double> ratios;
    for (const TileGroupSurface& g : b.cache.groups()) {
        std::vector<std::uint64_t> ids;
        tiles_under(b.cache, g, ids);
        TriMesh full;
        for (const std::uint64_t t : ids) {
            const TriMesh& m = tile(b.cache, t)->mesh;
            const auto base = static_cast<std::uint32_t>(full.positions.size());
            full.positions.insert(full.positions.end(), m.positions.begin(), m.positions.end());
            for (auto tri : m.triangles) full.triangles.push_back({tri[0] + base, tri[1] + base, tri[2] + base});
        }
        TriangleGrid to_full(full, 0.0);
        for (const TileLodLevel& l : g.lods) {
            TriangleGrid to_level(l.mesh, 0.0);
            const double d = std::max(max_distance(surface_samples(l.mesh, 0.2 * cell), to_full),
                                      max_distance(surface_samples(full, 0.2 * cell), to_level));
            ratios.push_back(d / l.error_m);
        }
        // Coarser levels, larger errors.
        for (std::size_t k = 1; k < g.lods.size(); ++k) EXPECT_GT(g.lods[k].error_m, g.lods[k - 1].error_m);
    }
    return ratios;
}

TEST(TileGroupLod, LevelsLieWithinTheirBoundOfTheFullSurface) {
    // Sampled bounds of the tiles' levels and of each group's own simplification add up to a bound of the full
    // surface (the group is simplified from its tiles' levels).
    const std::vector<double> ratios = group_level_ratios(sphere(64, LodErrorMeasure::kSampledBound));
    EXPECT_GT(ratios.size(), 4u);
    for (const double r : ratios) EXPECT_LE(r, 1.0);
}

TEST(TileGroupLod, EstimatedErrorsFollowTheFullSurface) {
    // meshoptimizer's estimates (times TileLodOptions::estimate_factor) are not bounds, but the distance to the
    // full surface stays near them: the renderer's one-pixel choice then strays by about a pixel at most.
    std::vector<double> ratios = group_level_ratios(sphere(64));
    ASSERT_GT(ratios.size(), 4u);
    std::sort(ratios.begin(), ratios.end());
    std::printf("group levels: distance / error_m median %.3f, largest %.3f of %zu\n", ratios[ratios.size() / 2],
                ratios.back(), ratios.size());
    EXPECT_LE(ratios[ratios.size() / 2], 1.0);
    EXPECT_LE(ratios.back(), 1.5);
}

TEST(TileGroupLod, FlatFacesCollapseAcrossTileBorders) {
    const Built b = box(128);
    std::size_t flat_groups = 0;
    for (const TileGroupSurface& g : b.cache.groups()) {
        if (g.depth != 1 || g.lods.empty()) continue;
        std::vector<std::uint64_t> ids;
        tiles_under(b.cache, g, ids);
        bool flat = true;
        std::size_t coarsest_tiles = 0;
        Vec3 n0(0.0);
        for (const std::uint64_t t : ids) {
            const TileSurface& s = *tile(b.cache, t);
            for (const Vec3& n : vertex_normals(s.mesh)) {
                if (n0 == Vec3(0.0)) n0 = n;
                flat = flat && glm::length(n - n0) < 1e-9;
            }
            coarsest_tiles += s.lods.empty() ? s.mesh.triangles.size() : s.lods.back().mesh.triangles.size();
        }
        if (!flat || ids.size() < 4) continue;
        ++flat_groups;
        // The strips along the inner tile borders go: far fewer triangles than the tiles' coarsest levels.
        EXPECT_LT(2 * g.lods.back().mesh.triangles.size(), coarsest_tiles) << "group " << g.id;
        EXPECT_LE(g.lods.back().error_m, 0.5 * b.model.lattice.cell_m) << "group " << g.id;
    }
    EXPECT_GE(flat_groups, 4u);
}

TEST(TileGroupLod, DirtyTilesRebuildTheirGroupsOnly) {
    Built b = sphere(96);
    b.cache.defer_lods(true);
    std::map<std::uint64_t, std::uint64_t> before, tile_before;
    for (const TileGroupSurface& g : b.cache.groups()) before[g.id] = g.version;
    for (const TileSurface& t : b.cache.tiles()) tile_before[t.id] = t.version;
    // A ball swept through the surface near +x.
    const Lattice& l = b.model.lattice;
    subtract_capsule(b.model, Segment{l.to_world(Vec3(80.0, 47.5, 48.3)), l.to_world(Vec3(90.0, 49.5, 50.1))}, 5.0 * l.cell_m);
    b.contourer.update(b.model);
    const std::size_t rebuilt = b.cache.refresh(b.contourer);
    ASSERT_GT(rebuilt, 0u);
    std::set<std::uint64_t> changed_tiles;
    for (const TileSurface& t : b.cache.tiles())
        if (!tile_before.count(t.id) || tile_before[t.id] != t.version) changed_tiles.insert(t.id);
    std::size_t stale = 0, kept = 0;
    for (const TileGroupSurface& g : b.cache.groups()) {
        std::vector<std::uint64_t> ids;
        tiles_under(b.cache, g, ids);
        const bool touched = std::any_of(ids.begin(), ids.end(), [&](std::uint64_t t) { return changed_tiles.count(t); });
        if (touched) {
            EXPECT_TRUE(g.lods.empty()) << "group " << g.id;  // never drawn with the old shape
            EXPECT_NE(g.version, before[g.id]);
            ++stale;
        } else if (before.count(g.id)) {
            EXPECT_EQ(g.version, before[g.id]) << "group " << g.id;
            ++kept;
        }
    }
    EXPECT_GE(stale, 3u);  // at least one group per depth
    EXPECT_GT(kept, stale);
    EXPECT_GE(b.cache.lod_pending(), rebuilt + stale);
    // Idle passes: the tiles first, then their groups finest first, each with a new version.
    while (b.cache.build_pending_lods(4) > 0) {
    }
    EXPECT_EQ(b.cache.lod_pending(), 0u);
    for (const TileGroupSurface& g : b.cache.groups())
        if (before.count(g.id) && g.version != before[g.id]) {
            EXPECT_FALSE(g.lods.empty()) << "group " << g.id;
        }
    // The rebuilt groups equal a fresh build of the changed model.
    TileSurfaceCache fresh;
    TileLodOptions o;
    o.cell_m = l.cell_m;
    fresh.enable_lod(o);
    fresh.refresh(b.contourer);
    ASSERT_EQ(fresh.groups().size(), b.cache.groups().size());
    for (std::size_t i = 0; i < b.cache.groups().size(); ++i) {
        const TileGroupSurface& x = b.cache.groups()[i];
        const TileGroupSurface& y = fresh.groups()[i];
        ASSERT_EQ(x.lods.size(), y.lods.size()) << "group " << x.id;
        for (std::size_t k = 0; k < x.lods.size(); ++k) EXPECT_EQ(x.lods[k].mesh.triangles, y.lods[k].mesh.triangles);
    }
}

TEST(TileGroupLod, GroupsFollowCutsAndAdditionsAsAFreshGroupingWould) {
    // A refresh regroups only the groups over tiles that changed. A ball in one corner of a 128-cell lattice (8 x 8 x 8
    // tiles); after a groove, a bead added in the empty far corner (new tiles, new groups), the bead cut away again
    // (tiles and groups gone) and a cap cut off the ball, every group equals a fresh cache's: id, depth, coordinates,
    // parent, children and bounds.
    const Vec3 centre(30.3, 29.8, 30.1);
    Built b = build(128, [&](int a, int u, int v) { return sphere_chord(centre, 20.0, a, u, v); });
    const Lattice& l = b.model.lattice;
    const auto sweep = [&](ToolOp op, const Vec3& from, const Vec3& to, double radius_cells) {
        Sweep s;
        s.op = op;
        s.tool.radius_m = radius_cells * l.cell_m;
        s.path_m = Segment{l.to_world(from), l.to_world(to)};
        apply_sweep(b.model, s);
        b.contourer.update(b.model);
        b.cache.refresh(b.contourer);
    };
    const auto same_as_fresh = [&](const char* what) {
        SCOPED_TRACE(what);
        TileSurfaceCache fresh;
        TileLodOptions o;
        o.cell_m = l.cell_m;
        o.group_depth = 3;
        fresh.enable_lod(o);
        fresh.refresh(b.contourer);
        ASSERT_EQ(fresh.groups().size(), b.cache.groups().size());
        for (std::size_t i = 0; i < fresh.groups().size(); ++i) {
            const TileGroupSurface& x = b.cache.groups()[i];
            const TileGroupSurface& y = fresh.groups()[i];
            ASSERT_EQ(x.id, y.id) << i;
            EXPECT_EQ(x.depth, y.depth) << x.id;
            EXPECT_EQ(x.coords, y.coords) << x.id;
            EXPECT_EQ(x.parent, y.parent) << x.id;
            EXPECT_EQ(x.children, y.children) << x.id;
            EXPECT_EQ(x.bounds_m.lo, y.bounds_m.lo) << x.id;
            EXPECT_EQ(x.bounds_m.hi, y.bounds_m.hi) << x.id;
        }
    };
    const std::size_t groups0 = b.cache.groups().size(), tiles0 = b.cache.tiles().size();
    sweep(ToolOp::kSubtract, Vec3(5.0, 30.0, 30.0), Vec3(55.0, 31.0, 31.5), 4.0);
    same_as_fresh("a groove");
    sweep(ToolOp::kUnion, Vec3(100.0, 100.0, 100.0), Vec3(108.0, 101.0, 102.0), 4.0);
    same_as_fresh("a bead added");
    EXPECT_GT(b.cache.groups().size(), groups0) << "the bead made new groups";
    sweep(ToolOp::kSubtract, Vec3(100.0, 100.0, 100.0), Vec3(108.0, 101.0, 102.0), 8.0);
    same_as_fresh("the bead cut away");
    EXPECT_EQ(b.cache.groups().size(), groups0) << "its groups went with it";
    sweep(ToolOp::kSubtract, Vec3(30.0, 30.0, 64.0), Vec3(30.0, 30.0, 60.0), 22.0);  // the top of the ball
    same_as_fresh("a cap cut off");
    EXPECT_LT(b.cache.tiles().size(), tiles0) << "the cap's tiles were emptied";
}

TEST(TileGroupLod, MergeWeldsSharedVerticesAndRefusesBadInput) {
    TriMesh a, c;
    a.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    a.triangles = {{0, 1, 2}};
    c.positions = {Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    c.triangles = {{0, 1, 2}};
    const std::vector<std::uint8_t> mats{3, 3, 3};
    const std::vector<LodPart> parts{{&a, mats, {}, 0.0}, {&c, {}, {}, 0.0}};
    std::vector<std::uint8_t> m;
    std::vector<Vec3> n;
    const TriMesh merged = merge_lod_parts(parts, m, n);
    EXPECT_EQ(merged.positions.size(), 4u);
    EXPECT_EQ(merged.triangles.size(), 2u);
    ASSERT_EQ(m.size(), 4u);
    EXPECT_EQ(m[0], 3);
    EXPECT_EQ(m[3], 0);
    for (const Vec3& v : n) EXPECT_NEAR(glm::length(v), 1.0, 1e-12);
    const std::vector<std::uint8_t> wrong{1};
    const std::vector<LodPart> bad{{&a, wrong, {}, 0.0}};
    EXPECT_THROW(merge_lod_parts(bad, m, n), Error);
    TriMesh broken = a;
    broken.triangles = {{0, 1, 7}};
    const std::vector<LodPart> bad_index{{&broken, {}, {}, 0.0}};
    EXPECT_THROW(merge_lod_parts(bad_index, m, n), Error);
    TileLodOptions o;
    o.cell_m = 0.01;
    const std::vector<LodPart> bad_error{{&a, {}, {}, -1.0}};
    EXPECT_THROW(build_group_lod(bad_error, o), Error);
}

}  // namespace
}  // namespace tridex::compute
