// Tests of group levels contoured from the model read at coarser strides (compute/contour/coarse_levels.hpp and
// TileSurfaceCache::use_coarse_groups): every group has its level at once, near the analytic sphere; a ring and a
// skirt reach past the group's box; a cut drops the levels within reach and rebuilds them, equal to a fresh build
// (after the stroke, when it is a stroke's).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <thread>

#include "compute/contour/coarse_levels.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/mesh/mesh_weld.hpp"
#include "compute/tools/boolean.hpp"
#include "core/error.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;

const Vec3 kCentre = kOffCentre;  // grid units on a 128-cell cube lattice
constexpr double kRadius = kOffCentreRadius;

TriDexel sphere_model() { return off_centre_sphere(); }

// Coarse levels at depths 1-3 (the default).
CoarseLevelOptions every_depth() { return CoarseLevelOptions{}; }

// Levels on `cache` for `model` as `contourer` contours it: enable_lod, use_coarse_groups(options), the first refresh.
void start_coarse(TileSurfaceCache& cache, const TriDexel& model, const Contourer& contourer,
                  const CoarseLevelOptions& options) {
    TileLodOptions o;
    o.cell_m = model.lattice.cell_m;
    cache.enable_lod(o);
    cache.use_coarse_groups(model, options);
    cache.refresh(contourer);
}

struct Session {
    TriDexel model = sphere_model();
    Contourer contourer{model};
    TileSurfaceCache cache;

    Session() {
        contourer.update(model);
        start_coarse(cache, model, contourer, every_depth());
        // The first refresh built the coarser groups' levels; the finest come through collect_lods().
        for (const TileGroupSurface& g : cache.groups())
            if (g.depth >= TileSurfaceCache::kCoarseStartupDepth) {
                EXPECT_FALSE(g.lods.empty()) << g.id;
            }
        waited_at_start = cache.coarse_waiting();
        while (cache.coarse_waiting() > 0) EXPECT_GT(cache.collect_lods(), 0u);
    }
    std::size_t waited_at_start = 0;
};

double radial_error_m(const TriMesh& m, std::size_t vertices, const Lattice& L) {
    const Vec3 c = L.to_world(kCentre);
    double worst = 0.0;
    for (std::size_t i = 0; i < vertices && i < m.positions.size(); ++i)
        worst = std::max(worst, std::abs(glm::length(m.positions[i] - c) - kRadius * L.cell_m));
    return worst;
}

TEST(CoarseGroups, EveryGroupHasItsLevelFromTheFirstRefreshNearTheSphere) {
    Session s;
    const double h = s.model.lattice.cell_m;
    ASSERT_FALSE(s.cache.groups().empty());
    std::size_t with_level = 0;
    double worst[4] = {0.0, 0.0, 0.0, 0.0}, worst_error[4] = {0.0, 0.0, 0.0, 0.0};
    for (const TileGroupSurface& g : s.cache.groups()) {
        ASSERT_LE(g.lods.size(), 1u);
        if (g.lods.empty()) continue;
        ++with_level;
        const TileLodLevel& l = g.lods[0];
        // The measured distance from the tiles' vertices: under a coarse cell on a sphere, and never zero.
        EXPECT_GT(l.error_m, 0.0);
        EXPECT_LT(l.error_m, h * (1 << g.depth)) << g.depth;
        worst_error[g.depth] = std::max(worst_error[g.depth], l.error_m);
        ASSERT_EQ(l.materials.size(), l.mesh.positions.size());
        ASSERT_EQ(l.normals.size(), l.mesh.positions.size());
        // The skirt's vertices lie one coarse cell inside; the others on the coarse contour.
        const double skirt = h * (1 << g.depth);
        for (const Vec3& p : l.mesh.positions) {
            const double r = glm::length(p - s.model.lattice.to_world(kCentre));
            EXPECT_LT(std::abs(r - kRadius * h), 0.1 * skirt + skirt * 1.01) << g.depth;
        }
        worst[g.depth] = std::max(worst[g.depth], radial_error_m(l.mesh, l.mesh.positions.size() / 2, s.model.lattice));
    }
    // Every group over surface tiles has a level (a sphere leaves none without surface near it); the depth-1 ones
    // came after the first refresh.
    EXPECT_EQ(with_level, s.cache.groups().size());
    const auto depth1 = std::count_if(s.cache.groups().begin(), s.cache.groups().end(),
                                      [](const TileGroupSurface& g) { return g.depth == 1; });
    EXPECT_EQ(s.waited_at_start, static_cast<std::size_t>(depth1));
    std::printf("[coarse groups] %zu groups; depth 1-3 contour vertices within %.3f / %.3f / %.3f fine cells of the "
                "sphere; measured level errors up to %.3f / %.3f / %.3f fine cells\n",
                with_level, worst[1] / h, worst[2] / h, worst[3] / h, worst_error[1] / h, worst_error[2] / h,
                worst_error[3] / h);
    EXPECT_EQ(s.cache.lod_pending(), 0u);  // the tiles' own levels: no worker, built by refresh
}

// The level reaches past its group's box (the ring) and hangs a skirt from its border: two windings per skirt
// quad, so it shows from either side.
TEST(CoarseGroups, TheRingReachesPastTheBoxAndTheSkirtHangsFromItsBorder) {
    const TriDexel model = sphere_model();
    CoarseGroupLevels levels(model, every_depth());
    const Lattice& L = model.lattice;
    for (int depth = 1; depth <= 2; ++depth) {  // a depth-3 group holds the whole 128-cell lattice
        const int span = TileGrid::kTileCells << depth;
        // The group holding the sphere's top (+z) pole.
        const std::array<int, 3> g{static_cast<int>(kCentre.x) / span, static_cast<int>(kCentre.y) / span,
                                   static_cast<int>(kCentre.z + kRadius) / span};
        const TileLodLevel l = levels.level(depth, g);
        ASSERT_FALSE(l.mesh.triangles.empty()) << depth;
        const Vec3 lo = L.to_world(Vec3(g[0], g[1], g[2]) * double(span)), hi = lo + Vec3(span * L.cell_m);
        double past = 0.0;
        for (const Vec3& p : l.mesh.positions)
            for (int a = 0; a < 3; ++a) past = std::max({past, lo[a] - p[a], p[a] - hi[a]});
        EXPECT_GT(past, 0.5 * L.cell_m * (1 << depth)) << depth;  // at least half a coarse cell past
        EXPECT_LT(past, 3.0 * L.cell_m * (1 << depth)) << depth;
        TriMesh copy = l.mesh;
        std::vector<std::uint8_t> mats = l.materials;
        std::vector<Vec3> normals = l.normals;
        EXPECT_EQ(add_skirt(copy, mats, normals, 1e-3), 0u) << "the skirt already closes every border edge on one side";
    }
    EXPECT_THROW((void)levels.level(4, {0, 0, 0}), Error);
    EXPECT_THROW((void)levels.level(1, {99, 0, 0}), Error);
}

// A level's own triangles come first: its coarse tile's contour. Drawn at one depth without rings and skirts, the
// own triangles of every group close the sphere, and each open border edge of a group's own triangles is an edge of
// the own triangles of a neighbour its joins name.
TEST(CoarseGroups, OwnTrianglesFirstAndTheirBorderMeetsTheJoinedNeighbours) {
    const TriDexel model = sphere_model();
    CoarseGroupLevels levels(model, every_depth());
    using Edge = std::pair<std::array<double, 3>, std::array<double, 3>>;
    const auto edge_of = [](const Vec3& a, const Vec3& b) {
        const std::array<double, 3> x{a.x, a.y, a.z}, y{b.x, b.y, b.z};
        return x < y ? Edge{x, y} : Edge{y, x};
    };
    for (int depth = 1; depth <= 3; ++depth) {
        std::array<int, 3> dims{};
        for (int a = 0; a < 3; ++a) dims[a] = (model.tiles.tiles[a] + (1 << depth) - 1) >> depth;
        std::map<std::array<int, 3>, TileLodLevel> at;
        TriMesh own_soup;
        for (int z = 0; z < dims[2]; ++z)
            for (int y = 0; y < dims[1]; ++y)
                for (int x = 0; x < dims[0]; ++x) {
                    TileLodLevel l = levels.level(depth, {x, y, z});
                    if (l.mesh.triangles.empty()) continue;
                    ASSERT_GT(l.own_triangles, 0u) << depth;
                    ASSERT_LE(l.own_triangles, l.mesh.triangles.size()) << depth;
                    if (depth < 3) {  // at depth 3 one group holds the closed sphere: nothing to ring
                        EXPECT_LT(l.own_triangles, l.mesh.triangles.size()) << depth << ": a ring or skirt follows";
                    }
                    EXPECT_EQ(l.joins & (1u << neighbour_bit(0, 0, 0)), 0u);
                    for (std::size_t i = 0; i < l.own_triangles; ++i) {
                        const auto base = static_cast<std::uint32_t>(own_soup.positions.size());
                        for (const std::uint32_t v : l.mesh.triangles[i]) own_soup.positions.push_back(l.mesh.positions[v]);
                        own_soup.triangles.push_back({base, base + 1, base + 2});
                    }
                    at.emplace(std::array<int, 3>{x, y, z}, std::move(l));
                }
        ASSERT_FALSE(at.empty()) << depth;
        TriMesh closed = weld_exact(own_soup);
        EXPECT_NO_THROW(require_closed_outward(closed, "depth " + std::to_string(depth) + " own triangles"));
        // Per group: its own triangles' edges, counted.
        std::map<std::array<int, 3>, std::map<Edge, int>> edges;
        for (const auto& [c, l] : at)
            for (std::size_t i = 0; i < l.own_triangles; ++i)
                for (int k = 0; k < 3; ++k)
                    ++edges[c][edge_of(l.mesh.positions[l.mesh.triangles[i][k]],
                                       l.mesh.positions[l.mesh.triangles[i][(k + 1) % 3]])];
        std::size_t border = 0, joined = 0;
        for (const auto& [c, l] : at) {
            if (depth == 3) {
                EXPECT_EQ(l.joins, 0u) << "one group holds the whole lattice";
            }
            for (const auto& [e, n] : edges[c]) {
                if (n != 1) continue;
                ++border;
                bool found = false;
                for (int dz = -1; dz <= 1 && !found; ++dz)
                    for (int dy = -1; dy <= 1 && !found; ++dy)
                        for (int dx = -1; dx <= 1 && !found; ++dx) {
                            if (!(l.joins & (1u << neighbour_bit(dx, dy, dz)))) continue;
                            const auto it = edges.find({c[0] + dx, c[1] + dy, c[2] + dz});
                            found = it != edges.end() && it->second.count(e) != 0;
                        }
                EXPECT_TRUE(found) << "depth " << depth << ": a border edge of group " << c[0] << "," << c[1] << ","
                                   << c[2] << " in no joined neighbour's own triangles";
                joined += found ? 1 : 0;
            }
        }
        if (depth < 3) {
            EXPECT_GT(border, 0u) << depth;
        }
        std::printf("[coarse groups] depth %d: %zu groups, %zu own border edges, %zu met in joined neighbours\n", depth,
                    at.size(), border, joined);
    }
}

TEST(CoarseGroups, ASkirtQuadPerBorderEdgeInBothWindings) {
    TriMesh m;
    m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    m.triangles = {{0, 1, 2}};
    std::vector<std::uint8_t> mats{1, 2, 3};
    std::vector<Vec3> normals(3, Vec3(0, 0, 1));
    EXPECT_EQ(add_skirt(m, mats, normals, 0.5), 3u);
    EXPECT_EQ(m.positions.size(), 6u);
    EXPECT_EQ(m.triangles.size(), 1u + 3u * 4u);
    for (std::size_t i = 3; i < 6; ++i) EXPECT_DOUBLE_EQ(m.positions[i].z, -0.5);
    EXPECT_EQ(mats[3] + mats[4] + mats[5], 6);
    std::vector<Vec3> short_normals(2);
    EXPECT_THROW(add_skirt(m, mats, short_normals, 0.5), Error);
}

// Expects every group level of `cache` (settled) to equal, bit for bit, those of a cache built afresh on the sphere
// cut by `cut_model`; returns how many levels it compared.
template <typename Cut>
std::size_t expect_levels_of_a_fresh_build(const TileSurfaceCache& cache, Cut cut_model) {
    Session fresh;  // built on the sphere, then cut the same way
    cut_model(fresh.model);
    TriDexel cut = fresh.model;
    Contourer c(cut);
    cut.tiles.dirty.assign(cut.tiles.dirty.size(), TileGrid::kWhole);
    c.update(cut);
    TileSurfaceCache again;
    start_coarse(again, cut, c, every_depth());
    while (again.coarse_waiting() > 0)
        if (again.collect_lods() == 0) {
            ADD_FAILURE() << "a settle pass of the fresh build built nothing";
            break;
        }
    EXPECT_EQ(again.groups().size(), cache.groups().size());
    std::size_t compared = 0;
    for (std::size_t i = 0; i < again.groups().size() && i < cache.groups().size(); ++i) {
        const TileGroupSurface &a = again.groups()[i], &b = cache.groups()[i];
        EXPECT_EQ(a.id, b.id);
        EXPECT_EQ(a.lods.size(), b.lods.size()) << a.id;
        if (a.lods.empty() || b.lods.empty()) continue;
        EXPECT_EQ(a.lods[0].mesh.positions, b.lods[0].mesh.positions) << a.id;
        EXPECT_EQ(a.lods[0].mesh.triangles, b.lods[0].mesh.triangles) << a.id;
        EXPECT_EQ(a.lods[0].materials, b.lods[0].materials) << a.id;
        EXPECT_EQ(a.lods[0].error_m, b.lods[0].error_m) << a.id;
        ++compared;
    }
    return compared;
}

// A cut drops the levels of the groups within reach (their children are drawn), keeps the others, and after the
// settling the rebuilt levels equal those of a cache built afresh on the cut model, bit for bit.
TEST(CoarseGroups, ACutRebuildsTheCoarsestLevelsAtOnceAndTheRestOnceSettledAsAFreshBuildWould) {
    Session s;
    std::map<std::uint64_t, std::uint64_t> before;
    for (const TileGroupSurface& g : s.cache.groups()) before[g.id] = g.version;
    const Lattice& L = s.model.lattice;
    const Vec3 top = L.to_world(kCentre + Vec3(0.0, 0.0, kRadius));
    subtract_capsule(s.model, Segment{top + Vec3(-0.01, 0.0, 0.0), top + Vec3(0.01, 0.0, 0.0)}, 0.004);
    s.contourer.update(s.model);
    s.cache.refresh(s.contourer);
    // The coarsest groups within reach are rebuilt by the refresh itself; the finer ones are dropped until settled.
    const int top_depth = every_depth().max_depth;
    std::size_t dropped = 0, kept = 0, at_once = 0;
    std::set<std::uint64_t> dropped_ids;
    for (const TileGroupSurface& g : s.cache.groups()) {
        if (g.version == before[g.id]) {
            ++kept;
        } else if (g.depth == top_depth) {
            EXPECT_EQ(g.lods.size(), 1u) << g.id;
            ++at_once;
        } else {
            EXPECT_TRUE(g.lods.empty()) << g.id;
            dropped_ids.insert(g.id);
            ++dropped;
        }
        EXPECT_EQ(g.levels_waiting, dropped_ids.count(g.id) != 0) << g.id;  // what a renderer stands in for
    }
    EXPECT_GT(dropped, 0u);
    EXPECT_GT(kept, 0u);
    EXPECT_GT(at_once, 0u);
    EXPECT_EQ(s.cache.coarse_waiting(), dropped);
    // The coarsest depth waiting comes back first: no dropped group is back while a coarser one still waits.
    std::set<int> depths;
    while (s.cache.coarse_waiting() > 0) {
        ASSERT_GT(s.cache.collect_lods(), 0u);
        int coarsest_waiting = 0;
        for (const TileGroupSurface& g : s.cache.groups())
            if (g.levels_waiting) coarsest_waiting = std::max(coarsest_waiting, g.depth);
        for (const TileGroupSurface& g : s.cache.groups())
            if (dropped_ids.count(g.id) != 0 && !g.levels_waiting) {
                EXPECT_GE(g.depth, coarsest_waiting) << g.id;
                depths.insert(g.depth);
            }
    }
    EXPECT_GT(depths.size(), 1u) << "the cut must drop levels at more than one depth";
    for (const TileGroupSurface& g : s.cache.groups()) EXPECT_FALSE(g.levels_waiting) << g.id;
    const std::size_t compared = expect_levels_of_a_fresh_build(s.cache, [&](TriDexel& m) {
        subtract_capsule(m, Segment{top + Vec3(-0.01, 0.0, 0.0), top + Vec3(0.01, 0.0, 0.0)}, 0.004);
    });
    EXPECT_EQ(compared, s.cache.groups().size());
}

// Two grooves around the sphere (its equator and a meridian), as a stroke's passes cut them: while the stroke is open
// no pass re-reads the finer coarse models or rebuilds a level they give; after it, passes re-read the changed tiles
// kCoarseUpdateTiles at a time and rebuild the levels once all are read, equal to a fresh build of the cut sphere.
void cut_grooves(TriDexel& m) {
    const Lattice& L = m.lattice;
    constexpr int kSegments = 16;
    for (int ring = 0; ring < 2; ++ring)
        for (int i = 0; i < kSegments; ++i) {
            const auto on = [&](int k) {
                const double t = 2.0 * 3.14159265358979 * k / kSegments;
                const Vec3 p = ring == 0 ? Vec3(std::cos(t), std::sin(t), 0.0) : Vec3(std::cos(t), 0.0, std::sin(t));
                return L.to_world(kCentre + kRadius * p);
            };
            subtract_capsule(m, Segment{on(i), on(i + 1)}, 4.0 * L.cell_m);
        }
}

TEST(CoarseGroups, AStrokesCutIsReadAfterItsCloseABatchAtATimeAsAFreshBuildWould) {
    Session s;
    cut_grooves(s.model);
    const std::vector<std::uint32_t> dirty = s.model.tiles.dirty_tiles();
    ASSERT_GT(dirty.size(), TileSurfaceCache::kCoarseUpdateTiles) << "the grooves must need more than one batch";
    s.contourer.update(s.model);
    s.cache.refresh(s.contourer);
    const std::size_t waiting = s.cache.coarse_waiting();
    ASSERT_GT(waiting, 0u);
    std::map<std::uint64_t, std::uint64_t> versions;
    for (const TileGroupSurface& g : s.cache.groups()) versions[g.id] = g.version;
    for (int i = 0; i < 10; ++i) EXPECT_EQ(s.cache.collect_lods(true), 0u) << "a pass during the stroke built levels";
    EXPECT_EQ(s.cache.coarse_waiting(), waiting);
    for (const TileGroupSurface& g : s.cache.groups()) EXPECT_EQ(g.version, versions[g.id]) << g.id;
    int passes = 0;
    while (s.cache.coarse_waiting() > 0 && passes < 1000) {
        s.cache.collect_lods(false);
        ++passes;
    }
    EXPECT_EQ(s.cache.coarse_waiting(), 0u);
    EXPECT_GT(expect_levels_of_a_fresh_build(s.cache, cut_grooves), 0u);
}

// A cut into the sphere's top re-reads the coarse rays through its tiles and re-contours only the coarse tiles near
// the ends that moved: an interval the tool only entered keeps its far end, at the bottom, and nothing there is
// re-contoured. The levels still equal those of a fresh read of the cut model.
TEST(CoarseGroups, ACutReContoursOnlyTheCoarseTilesNearTheEndsThatMoved) {
    TriDexel model = sphere_model();
    CoarseGroupLevels levels(model, every_depth());
    model.tiles.dirty.assign(model.tiles.dirty.size(), 0);
    const Lattice& L = model.lattice;
    const Vec3 top = L.to_world(kCentre + Vec3(0.0, 0.0, kRadius));
    subtract_capsule(model, Segment{top + Vec3(-0.01, 0.0, 0.0), top + Vec3(0.01, 0.0, 0.0)}, 0.004);
    const std::vector<std::uint32_t> d = model.tiles.dirty_tiles();
    const std::vector<std::uint64_t> changed(d.begin(), d.end());
    ASSERT_FALSE(changed.empty());
    const std::size_t recontoured = levels.update(model, changed);
    // Per depth, the coarse tiles over the cut's tile columns, at most two layers of them (the cut lies in the top
    // two tile layers); a re-read that also took each z ray's unchanged bottom end re-contours tiles all the way down.
    std::size_t cut_columns = 0;
    for (int depth = 1; depth <= 3; ++depth) {
        const int span = 1 << depth;
        std::set<std::pair<int, int>> columns;
        for (const std::uint64_t t : changed)
            columns.insert({static_cast<int>(t % 8) / span, static_cast<int>(t / 8 % 8) / span});
        cut_columns += columns.size();
    }
    EXPECT_GT(recontoured, 0u);
    EXPECT_LE(recontoured, 2 * cut_columns) << "coarse tiles re-contoured for " << changed.size() << " cut tiles";
    const CoarseGroupLevels fresh(model, every_depth());
    for (int depth = 1; depth <= 3; ++depth) {
        const int groups = 128 / (TileGrid::kTileCells << depth);
        for (int z = 0; z < groups; ++z)
            for (int y = 0; y < groups; ++y)
                for (int x = 0; x < groups; ++x) {
                    const TileLodLevel a = fresh.level(depth, {x, y, z}), b = levels.level(depth, {x, y, z});
                    EXPECT_EQ(a.mesh.positions, b.mesh.positions) << depth << " " << x << y << z;
                    EXPECT_EQ(a.materials, b.materials) << depth << " " << x << y << z;
                }
    }
}

// A start-up with many groups of one depth builds their levels on every core (TileSurfaceCache::kParallelLodTiles
// and more): each level equals the one CoarseGroupLevels::level() gives on its own (run under ThreadSanitizer too).
TEST(CoarseGroups, ManyLevelsBuiltAtOnceEqualThoseBuiltOneByOne) {
    TriDexel model = empty_model(cube_lattice(192));
    fill_rays(model, [](int a, int u, int v) { return sphere_chord(Vec3(96.3, 95.8, 96.1), 80.4, a, u, v); });
    Contourer contourer(model);
    contourer.update(model);
    CoarseLevelOptions one_depth;
    one_depth.min_depth = one_depth.max_depth = 1;  // the deepest depth is built in the first refresh
    TileSurfaceCache cache;
    start_coarse(cache, model, contourer, one_depth);
    ASSERT_GE(cache.groups().size(), TileSurfaceCache::kParallelLodTiles);
    EXPECT_EQ(cache.coarse_waiting(), 0u);
    const CoarseGroupLevels alone(model, one_depth);
    for (const TileGroupSurface& g : cache.groups()) {
        ASSERT_EQ(g.lods.size(), 1u) << g.id;
        const TileLodLevel l = alone.level(g.depth, g.coords);
        EXPECT_EQ(g.lods[0].mesh.positions, l.mesh.positions) << g.id;
        EXPECT_EQ(g.lods[0].mesh.triangles, l.mesh.triangles) << g.id;
        EXPECT_GT(g.lods[0].error_m, 0.0) << g.id;
    }
}

// A depth read after the constructor (build_depth) contours its coarse tiles only as read_around() needs them, and
// each level then equals, vertex for vertex, the one of levels whose constructor contoured every depth whole.
TEST(CoarseGroups, ADepthReadLaterIsContouredWhereItsLevelsAreReadAndGivesTheSameLevels) {
    const TriDexel model = sphere_model();
    const CoarseGroupLevels whole(model, every_depth());
    CoarseGroupLevels later(model, every_depth(), 3);  // depth 3 only, as a coarse-first start-up
    EXPECT_FALSE(later.has_depth(1));
    later.build_depth(model, 1);
    later.build_depth(model, 2);
    ASSERT_TRUE(later.has_depth(1));
    const std::array<int, 3> pole{static_cast<int>(kCentre.x) / 32, static_cast<int>(kCentre.y) / 32,
                                  static_cast<int>(kCentre.z + kRadius) / 32};
    EXPECT_THROW((void)later.level(1, pole), Error) << "not read by read_around() yet";
    EXPECT_FALSE(later.contoured_around(1, pole));
    EXPECT_TRUE(whole.contoured_around(1, pole)) << "a depth contoured whole only reads";
    EXPECT_THROW((void)later.contoured_around(1, {-1, 0, 0}), Error);
    EXPECT_THROW((void)later.contoured_around(4, pole), Error);
    int compared = 0;
    for (int depth = 1; depth <= 2; ++depth) {
        const int groups = 128 / (TileGrid::kTileCells << depth);
        std::vector<std::pair<int, std::array<int, 3>>> where;
        for (int z = 0; z < groups; ++z)
            for (int y = 0; y < groups; ++y)
                for (int x = 0; x < groups; ++x)
                    if ((x + y + z) % 3 == 0) where.push_back({depth, {x, y, z}});  // a third of them, scattered
        later.read_around(where);
        for (const auto& [d, c] : where) {
            EXPECT_TRUE(later.contoured_around(d, c));
            const TileLodLevel a = whole.level(d, c), b = later.level(d, c);
            EXPECT_EQ(a.mesh.positions, b.mesh.positions) << d << " " << c[0] << c[1] << c[2];
            EXPECT_EQ(a.mesh.triangles, b.mesh.triangles) << d << " " << c[0] << c[1] << c[2];
            EXPECT_EQ(a.materials, b.materials);
            compared += !a.mesh.triangles.empty();
        }
        later.forget_reads();
    }
    EXPECT_GT(compared, 10);
}

// With min_depth 2 the depth-1 groups keep the levels simplified from their tiles (a stride-2 model would hold a
// quarter of the rays); depths 2 and 3 take coarse levels.
TEST(CoarseGroups, FromMinDepthTwoTheShallowestGroupsKeepSimplifiedLevels) {
    CoarseLevelOptions from_two;
    from_two.min_depth = 2;
    TriDexel model = sphere_model();
    Contourer contourer(model);
    contourer.update(model);
    TileSurfaceCache cache;
    start_coarse(cache, model, contourer, from_two);  // no worker: the simplified levels are built now
    EXPECT_EQ(cache.coarse_waiting(), 0u);
    std::size_t simplified = 0, coarse = 0;
    for (const TileGroupSurface& g : cache.groups()) {
        if (g.depth == 1) {
            simplified += g.lods.size();
        } else {
            ASSERT_EQ(g.lods.size(), 1u) << g.id;
            ++coarse;
        }
    }
    EXPECT_GT(simplified, 0u);
    EXPECT_GT(coarse, 0u);
    const CoarseGroupLevels levels(model, from_two);
    EXPECT_EQ(levels.min_depth(), 2);
    EXPECT_THROW((void)levels.level(1, {0, 0, 0}), Error);
}

// From min_depth 1 a tile's coarser level is its depth-1 group's: the tiles get no simplified levels of their own,
// whether built at once or by the worker (which still puts each tile's mesh in vertex-cache order: the same
// triangles). With min_depth 2 the tiles keep theirs, from which the depth-1 groups are simplified.
TEST(CoarseGroups, FromMinDepthOneTheTilesBuildNoLevelsOfTheirOwn) {
    // A mesh's triangles as position triples, each from its smallest corner on (the winding kept), in any order.
    const auto triangles = [](const TriMesh& m) {
        std::multiset<std::array<double, 9>> out;
        for (const auto& t : m.triangles) {
            std::array<std::array<double, 3>, 3> p{};
            for (int k = 0; k < 3; ++k) p[k] = {m.positions[t[k]].x, m.positions[t[k]].y, m.positions[t[k]].z};
            std::rotate(p.begin(), std::min_element(p.begin(), p.end()), p.end());
            std::array<double, 9> flat{};
            for (int k = 0; k < 9; ++k) flat[k] = p[k / 3][k % 3];
            out.insert(flat);
        }
        return out;
    };
    for (const bool background : {false, true}) {
        for (const int min_depth : {1, 2}) {
            SCOPED_TRACE(std::string(background ? "worker" : "at once") + ", min_depth " + std::to_string(min_depth));
            CoarseLevelOptions options;
            options.min_depth = min_depth;
            TriDexel model = sphere_model();
            Contourer contourer(model);
            contourer.update(model);
            TileSurfaceCache cache;
            TileLodOptions o;
            o.cell_m = model.lattice.cell_m;
            cache.enable_lod(o);
            if (background) cache.build_lods_in_background();
            cache.use_coarse_groups(model, options);
            cache.refresh(contourer);
            for (int i = 0; i < 20000 && (cache.lod_pending() > 0 || cache.coarse_waiting() > 0); ++i) {
                cache.collect_lods();
                std::this_thread::sleep_for(std::chrono::milliseconds(1));
            }
            ASSERT_EQ(cache.lod_pending(), 0u);
            std::size_t with_levels = 0, checked = 0;
            for (const TileSurface& t : cache.tiles()) {
                with_levels += !t.lods.empty();
                if (!background || t.mesh.triangles.empty()) continue;
                EXPECT_EQ(triangles(t.mesh), triangles(contourer.tile_mesh(static_cast<std::size_t>(t.id)))) << t.id;
                ++checked;
            }
            if (min_depth == 1) {
                EXPECT_EQ(with_levels, 0u);
            } else {
                EXPECT_GT(with_levels, 0u);
            }
            if (background) {
                EXPECT_GT(checked, 0u);
            }
            EXPECT_EQ(cache.lod_tiles_built(), cache.tiles().size());
        }
    }
}

TEST(CoarseGroups, RefusesBadOptionsAndALateCall) {
    const TriDexel model = sphere_model();
    CoarseLevelOptions o;
    o.max_depth = 0;
    EXPECT_THROW(CoarseGroupLevels(model, o), Error);
    o = {};
    o.min_depth = 4;  // deeper than max_depth
    EXPECT_THROW(CoarseGroupLevels(model, o), Error);
    o = {};
    o.skirt_coarse_cells = 0.0;
    EXPECT_THROW(CoarseGroupLevels(model, o), Error);
    TileSurfaceCache cache;
    EXPECT_THROW(cache.use_coarse_groups(model), Error);  // before enable_lod
    Session s;
    EXPECT_THROW(s.cache.use_coarse_groups(s.model), Error);  // after a refresh
}

}  // namespace
}  // namespace tridex::compute
