// Tests of compute/contour/tile_lod (per-tile levels of detail) and surface_distance: any mix of levels across
// tiles stays a closed manifold (border edges shared), every level lies within its sampled bound of the full
// mesh (dense samples, both directions) and near its estimated error, flat faces lose every interior vertex,
// levels built in the background equal those built at once, bad input is refused. The background worker's
// scheduling: test_contour_lod_worker.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <random>
#include <thread>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/lod_worker.hpp"
#include "compute/contour/surface_distance.hpp"
#include "compute/contour/tile_lod.hpp"
#include "core/error.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;

struct Built {
    TriDexel model;
    TileSurfaceCache cache;
};

// A model from chords, contoured, with its tile cache and levels of detail (in refresh(), or with `background` on
// the cache's worker until every one is built).
Built build(int cells, const std::function<std::vector<Interval>(int, int, int)>& chord,
            LodErrorMeasure measure = LodErrorMeasure::kEstimate, bool background = false) {
    Built b{empty_model(cube_lattice(cells)), {}};
    fill_rays(b.model, chord);
    Contourer c(b.model);
    c.update(b.model);
    TileLodOptions o;
    o.cell_m = b.model.lattice.cell_m;
    o.measure = measure;
    b.cache.enable_lod(o);
    if (background) b.cache.build_lods_in_background();
    b.cache.refresh(c);
    while (background && b.cache.lod_pending() > 0) {
        b.cache.collect_lods();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return b;
}

Built sphere(int cells, LodErrorMeasure measure = LodErrorMeasure::kEstimate, bool background = false) {
    const Vec3 centre(0.5 * cells + 0.31, 0.5 * cells - 0.17, 0.5 * cells + 0.07);
    const double r = 0.38 * cells;
    return build(cells, [&](int a, int u, int v) { return sphere_chord(centre, r, a, u, v); }, measure, background);
}

Built box(int cells) {
    const Vec3 lo(3.3, 4.4, 2.6), hi(cells - 3.7, cells - 2.2, cells - 4.1);
    return build(cells, [&](int a, int u, int v) { return box_chord(lo, hi, a, u, v); });
}

// The tiles at the given levels (0 = full mesh, k = lods[k - 1]) welded by exact position into one mesh.
TriMesh assemble(const TileSurfaceCache& cache, const std::vector<std::size_t>& level) {
    TriMesh out;
    std::map<std::array<double, 3>, std::uint32_t> index;
    for (std::size_t i = 0; i < cache.tiles().size(); ++i) {
        const TileSurface& s = cache.tiles()[i];
        const TriMesh& m = level[i] == 0 ? s.mesh : s.lods[level[i] - 1].mesh;
        for (const auto& t : m.triangles) {
            std::array<std::uint32_t, 3> w{};
            for (int k = 0; k < 3; ++k) {
                const Vec3& p = m.positions[t[k]];
                const auto [it, fresh] = index.try_emplace({p.x, p.y, p.z}, static_cast<std::uint32_t>(out.positions.size()));
                if (fresh) out.positions.push_back(p);
                w[k] = it->second;
            }
            out.triangles.push_back(w);
        }
    }
    return out;
}

std::size_t total_triangles(const TileSurfaceCache& cache, bool coarsest) {
    std::size_t n = 0;
    for (const TileSurface& s : cache.tiles())
        n += coarsest && !s.lods.empty() ? s.lods.back().mesh.triangles.size() : s.mesh.triangles.size();
    return n;
}

TEST(TileLod, MixedLevelsStayClosedManifold) {
    for (const bool flat : {false, true}) {
        const Built b = flat ? box(64) : sphere(64);
        const TileSurfaceCache& cache = b.cache;
        ASSERT_GT(cache.tiles().size(), 8u);
        std::size_t with_levels = 0;
        for (const TileSurface& s : cache.tiles()) with_levels += s.lods.empty() ? 0 : 1;
        EXPECT_GT(with_levels, cache.tiles().size() / 2) << "flat " << flat;
        // The coarsest levels hold far fewer triangles than the full meshes.
        EXPECT_LT(2 * total_triangles(cache, true), total_triangles(cache, false)) << "flat " << flat;
        std::mt19937 rng(flat ? 7u : 3u);
        for (int trial = 0; trial < 6; ++trial) {
            std::vector<std::size_t> level(cache.tiles().size());
            for (std::size_t i = 0; i < level.size(); ++i) {
                const std::size_t n = cache.tiles()[i].lods.size();
                // Trial 0: all full; 1: all coarsest; then random mixes, neighbours usually differing.
                level[i] = trial == 0 ? 0 : trial == 1 ? n : std::uniform_int_distribution<std::size_t>(0, n)(rng);
            }
            const TriMesh m = assemble(cache, level);
            SCOPED_TRACE(::testing::Message() << "flat " << flat << " trial " << trial);
            expect_closed_manifold(m);
        }
    }
}

// Largest distance from points spread at `spacing` over `from` to the surface `to`.
double sampled_distance(const TriMesh& from, const TriMesh& to, double spacing) {
    TriangleGrid grid(to, 0.0);
    return max_distance(surface_samples(from, spacing), grid);
}

// Per level of every tile of `b`: the two-sided distance to the tile's full mesh (samples a tenth of a cell apart,
// far denser than the bound's own) over its stored error_m; `largest` gets the largest distance, m.
std::vector<double> level_ratios(const Built& b, double& largest) {
    const double cell = b.model.lattice.cell_m;
    std::vector<double> ratios;
    largest = 0.0;
    for (const TileSurface& s : b.cache.tiles()) {
        for (std::size_t k = 0; k < s.lods.size(); ++k) {
            const TileLodLevel& l = s.lods[k];
            const double d = std::max(sampled_distance(s.mesh, l.mesh, 0.1 * cell), sampled_distance(l.mesh, s.mesh, 0.1 * cell));
            EXPECT_GT(l.error_m, 0.0);
            EXPECT_LT(l.error_m, 16.0 * cell) << "tile " << s.id << " level " << k + 1;
            if (k > 0) {
                EXPECT_GT(l.error_m, s.lods[k - 1].error_m) << "tile " << s.id;
            }
            // A coarser level is simplified from the finer one: fewer triangles.
            const std::size_t finer = k == 0 ? s.mesh.triangles.size() : s.lods[k - 1].mesh.triangles.size();
            EXPECT_LT(l.mesh.triangles.size(), finer);
            ratios.push_back(d / l.error_m);
            largest = std::max(largest, d);
        }
    }
    return ratios;
}

TEST(TileLod, LevelsLieWithinTheirSampledBound) {
    const Built b = sphere(48, LodErrorMeasure::kSampledBound);
    double largest = 0.0;
    const std::vector<double> ratios = level_ratios(b, largest);
    EXPECT_GT(ratios.size(), 20u);
    for (const double r : ratios) EXPECT_LE(r, 1.0);
    // The sphere is curved: its coarser levels really depart from it (the check above is not vacuous).
    EXPECT_GT(largest, 0.5 * b.model.lattice.cell_m);
}

TEST(TileLod, EstimatedErrorsFollowTheDistance) {
    // meshoptimizer's estimate (times estimate_factor) is no bound, but stays near the distance: the median level
    // lies well within it and none strays beyond one and a half times it.
    const Built b = sphere(48);
    double largest = 0.0;
    std::vector<double> ratios = level_ratios(b, largest);
    ASSERT_GT(ratios.size(), 20u);
    std::sort(ratios.begin(), ratios.end());
    std::printf("tile levels: distance / error_m median %.3f, p90 %.3f, largest %.3f of %zu\n", ratios[ratios.size() / 2],
                ratios[ratios.size() * 9 / 10], ratios.back(), ratios.size());
    EXPECT_LE(ratios[ratios.size() / 2], 0.8);
    EXPECT_LE(ratios.back(), 1.5);
    EXPECT_GT(largest, 0.5 * b.model.lattice.cell_m);
}

TEST(TileLod, BackgroundLevelsMatchThoseBuiltInRefresh) {
    const Built now = sphere(48);
    const Built later = sphere(48, LodErrorMeasure::kEstimate, true);
    ASSERT_EQ(now.cache.tiles().size(), later.cache.tiles().size());
    ASSERT_EQ(now.cache.groups().size(), later.cache.groups().size());
    EXPECT_EQ(later.cache.lod_tiles_built(), later.cache.tiles().size());
    for (std::size_t i = 0; i < now.cache.tiles().size(); ++i) {
        const TileSurface &a = now.cache.tiles()[i], &b = later.cache.tiles()[i];
        ASSERT_EQ(a.lods.size(), b.lods.size()) << "tile " << a.id;
        for (std::size_t k = 0; k < a.lods.size(); ++k) {
            EXPECT_EQ(a.lods[k].mesh.triangles, b.lods[k].mesh.triangles);
            EXPECT_EQ(a.lods[k].error_m, b.lods[k].error_m);
        }
    }
    for (std::size_t g = 0; g < now.cache.groups().size(); ++g) {
        const TileGroupSurface &a = now.cache.groups()[g], &b = later.cache.groups()[g];
        ASSERT_EQ(a.lods.size(), b.lods.size()) << "group " << a.id;
        for (std::size_t k = 0; k < a.lods.size(); ++k) {
            EXPECT_EQ(a.lods[k].mesh.triangles, b.lods[k].mesh.triangles);
            EXPECT_EQ(a.lods[k].error_m, b.lods[k].error_m);
        }
    }
}

TEST(TileLod, LevelsKeepAttributesOfTheFullMesh) {
    const Built b = sphere(48);
    for (const TileSurface& s : b.cache.tiles()) {
        // The full mesh's normals: the whole surface's at its vertices (Contourer::tile_mesh with normals).
        const std::vector<Vec3>& normals = s.normals;
        ASSERT_EQ(normals.size(), s.mesh.positions.size());
        std::map<std::array<double, 3>, std::size_t> at;
        for (std::size_t v = 0; v < s.mesh.positions.size(); ++v)
            at[{s.mesh.positions[v].x, s.mesh.positions[v].y, s.mesh.positions[v].z}] = v;
        for (const TileLodLevel& l : s.lods) {
            ASSERT_EQ(l.normals.size(), l.mesh.positions.size());
            ASSERT_EQ(l.materials.size(), l.mesh.positions.size());
            for (std::size_t v = 0; v < l.mesh.positions.size(); ++v) {
                const Vec3& p = l.mesh.positions[v];
                const auto it = at.find({p.x, p.y, p.z});
                ASSERT_NE(it, at.end()) << "a level vertex is not a full-mesh vertex";
                EXPECT_EQ(l.normals[v], normals[it->second]);
                EXPECT_EQ(l.materials[v], s.materials[it->second]);
            }
        }
    }
}

// Open border edges of a tile mesh (edges used by one of its triangles).
std::size_t border_edges(const TriMesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) ++uses[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
    return static_cast<std::size_t>(std::count_if(uses.begin(), uses.end(), [](const auto& e) { return e.second == 1; }));
}

TEST(TileLod, FlatFacesCollapseToTheirBorder) {
    const Built b = box(64);
    const double cell = b.model.lattice.cell_m;
    std::size_t planar = 0;
    for (const TileSurface& s : b.cache.tiles()) {
        // A tile inside one face: every vertex normal is the same axis.
        const std::vector<Vec3> n = vertex_normals(s.mesh);
        const bool flat = std::all_of(n.begin(), n.end(), [&](const Vec3& v) { return glm::length(v - n[0]) < 1e-9; });
        if (!flat) continue;
        ++planar;
        ASSERT_FALSE(s.lods.empty()) << "tile " << s.id;
        const std::size_t border = border_edges(s.mesh);
        for (const TileLodLevel& l : s.lods) {
            // The plane is kept exactly: no error (but float rounding in meshoptimizer's estimate).
            EXPECT_LE(l.error_m, 1e-3 * cell) << "tile " << s.id;
        }
        // The coarsest level is about one triangle per border edge (the border stays for the neighbours):
        // a polygon of B border vertices without inner vertices has B - 2 triangles.
        const std::size_t coarsest = s.lods.back().mesh.triangles.size();
        EXPECT_LE(coarsest, border + 8) << "tile " << s.id;
        EXPECT_LT(4 * coarsest, s.mesh.triangles.size()) << "tile " << s.id;
        std::printf("flat tile %llu: %zu -> %zu triangles, %zu border edges\n", static_cast<unsigned long long>(s.id),
                    s.mesh.triangles.size(), coarsest, border);
    }
    EXPECT_GE(planar, 6u);
}

TEST(TileLod, DeferredLevelsArriveWithNewVersionsAndMatchImmediateOnes) {
    const Built now = box(40);
    Built later{empty_model(cube_lattice(40)), {}};
    const Vec3 lo(3.3, 4.4, 2.6), hi(40 - 3.7, 40 - 2.2, 40 - 4.1);
    fill_rays(later.model, [&](int a, int u, int v) { return box_chord(lo, hi, a, u, v); });
    Contourer c(later.model);
    c.update(later.model);
    TileLodOptions o;
    o.cell_m = later.model.lattice.cell_m;
    later.cache.enable_lod(o);
    later.cache.defer_lods(true);
    later.cache.refresh(c);
    const std::size_t n = later.cache.tiles().size();
    const std::size_t groups = later.cache.groups().size();
    ASSERT_GT(n, 3u);
    EXPECT_EQ(later.cache.lod_pending(), n + groups);
    std::vector<std::uint64_t> versions;
    for (const TileSurface& t : later.cache.tiles()) {
        EXPECT_TRUE(t.lods.empty());
        versions.push_back(t.version);
    }
    EXPECT_EQ(later.cache.build_pending_lods(3), 3u);
    EXPECT_EQ(later.cache.lod_pending(), n + groups - 3);
    EXPECT_EQ(later.cache.lod_tiles_built(), 3u);
    // A refresh without a contour change rebuilds nothing, whatever the new versions.
    EXPECT_EQ(later.cache.refresh(c), 0u);
    while (later.cache.build_pending_lods(1000) > 0) {
    }
    EXPECT_EQ(later.cache.lod_pending(), 0u);
    EXPECT_EQ(later.cache.build_pending_lods(10), 0u);
    ASSERT_EQ(now.cache.tiles().size(), n);
    for (std::size_t i = 0; i < n; ++i) {
        const TileSurface& a = later.cache.tiles()[i];
        const TileSurface& b = now.cache.tiles()[i];
        EXPECT_NE(a.version, versions[i]);  // published again: its content (the levels) changed
        ASSERT_EQ(a.lods.size(), b.lods.size());
        for (std::size_t k = 0; k < a.lods.size(); ++k) {
            EXPECT_EQ(a.lods[k].mesh.triangles, b.lods[k].mesh.triangles);
            EXPECT_EQ(a.lods[k].error_m, b.lods[k].error_m);
        }
    }
}

TEST(TileLod, RefusesBadInput) {
    TriMesh m;
    m.positions = {Vec3(0.0), Vec3(1.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0)};
    m.triangles = {{0, 1, 2}};
    TileLodOptions o;
    o.cell_m = 0.0;
    EXPECT_THROW(build_tile_lod(m, {}, o), Error);
    o.cell_m = 1e-3;
    const std::vector<std::uint8_t> two(2, 0);
    EXPECT_THROW(build_tile_lod(m, two, o), Error);
    o.error_cells = {1.0, 0.5};
    EXPECT_THROW(build_tile_lod(m, {}, o), Error);
    o.error_cells = {1.0};
    o.keep_fraction = 1.0;
    EXPECT_THROW(build_tile_lod(m, {}, o), Error);
    o.keep_fraction = 0.8;
    o.estimate_factor = 0.5;
    EXPECT_THROW(build_tile_lod(m, {}, o), Error);
    o.estimate_factor = 1.5;
    m.triangles = {{0, 1, 3}};
    EXPECT_THROW(build_tile_lod(m, {}, o), Error);
    m.triangles = {{0, 1, 2}};
    EXPECT_TRUE(build_tile_lod(m, {}, o).empty());  // too small to simplify
    TileSurfaceCache cache;
    o.cell_m = -1.0;
    EXPECT_THROW(cache.enable_lod(o), Error);
}

TEST(SurfaceDistance, ClosestPointAndGridMatchBruteForce) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    TriMesh m;
    for (int t = 0; t < 60; ++t) {
        const Vec3 c(u(rng), u(rng), u(rng));
        for (int k = 0; k < 3; ++k) m.positions.push_back(c + 0.2 * Vec3(u(rng), u(rng), u(rng)));
        m.triangles.push_back({static_cast<std::uint32_t>(3 * t), static_cast<std::uint32_t>(3 * t + 1),
                               static_cast<std::uint32_t>(3 * t + 2)});
    }
    // A degenerate (collinear) triangle too.
    m.positions.push_back(Vec3(0.0));
    m.positions.push_back(Vec3(0.1, 0.1, 0.1));
    m.positions.push_back(Vec3(0.3, 0.3, 0.3));
    m.triangles.push_back({180, 181, 182});
    TriangleGrid grid(m, 0.1);
    std::vector<Vec3> queries;
    double largest = 0.0;
    for (int q = 0; q < 300; ++q) {
        const Vec3 p = 1.5 * Vec3(u(rng), u(rng), u(rng));
        queries.push_back(p);
        double brute = 1e30;
        for (const auto& t : m.triangles) {
            const Vec3 c = closest_point_on_triangle(p, m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]);
            brute = std::min(brute, glm::length(p - c));
            // The closest point is no farther than any sampled point of the triangle.
            for (int i = 0; i <= 8; ++i)
                for (int j = 0; i + j <= 8; ++j) {
                    const Vec3& a = m.positions[t[0]];
                    const Vec3 s = a + (i / 8.0) * (m.positions[t[1]] - a) + (j / 8.0) * (m.positions[t[2]] - a);
                    ASSERT_LE(glm::length(p - c), glm::length(p - s) + 1e-12);
                }
        }
        EXPECT_NEAR(grid.distance(p), brute, 1e-12);
        largest = std::max(largest, brute);
        // A search that may stop early: at most `enough` when stopped, else the exact distance.
        const double enough = 0.5 * brute + 0.05 * (q % 3);
        const double early = grid.distance(p, enough);
        if (brute > enough) EXPECT_NEAR(early, brute, 1e-12);
        else {
            EXPECT_LE(early, enough);
            EXPECT_GE(early, brute - 1e-12);
        }
    }
    EXPECT_NEAR(max_distance(queries, grid), largest, 1e-12);
    EXPECT_EQ(max_distance({}, grid), 0.0);
    EXPECT_TRUE(std::isinf(TriangleGrid(TriMesh{}, 1.0).distance(Vec3(0.0))));
}

}  // namespace
}  // namespace tridex::compute
