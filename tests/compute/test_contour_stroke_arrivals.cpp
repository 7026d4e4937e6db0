// Tests of the coarsest group levels while a stroke drawn coarse (defer_tiles) has its tiles hidden and they arrive
// afterwards a batch at a time, before the levels settle: the arrivals regroup the groups over them, and the coarsest
// depth's levels are rebuilt at once wherever that drops them, so that what a frame draws and a cursor picks (the
// tiles in, and the groups whose children do not cover them) holds the whole surface after every refresh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/deferred_contour.hpp"
#include "compute/contour/held_tiles.hpp"
#include "compute/contour/refine_wanted.hpp"
#include "compute/contour/sorted_ids.hpp"
#include "compute/contour/tile_group_box.hpp"
#include "compute/tools/boolean.hpp"
#include "compute/tools/sweep.hpp"
#include "test_coarse_first_session.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;

// Depth-1 groups (2x2x2 tiles, stride 2) are the coarsest: under a deep, wide groove some tiles arrive without the
// surface they held and others with surface they never held, so their groups' children change when they arrive.
constexpr int kCoarsest = 1;
CoarseLevelOptions coarse_levels() {
    CoarseLevelOptions o;
    o.max_depth = kCoarsest;
    return o;
}

// Cut k (0..3) of a deep groove across the sphere's +z cap, along x (`side` 0) or along y (`side` 1), crossing near
// the cap's axis: a capsule of kGrooveRadius cells, its axis kGrooveAxis cells under the surface, each cut 12 cells
// on. Its floor (about z = 92.7 on the axis) reaches the tiles under z = 96 near the axis, inside the sphere before.
constexpr double kGrooveRadius = 12.0, kGrooveAxis = 8.0;
void deep_cut(TriDexel& m, int k, int side) {
    const Lattice& L = m.lattice;
    const double r = kOffCentreRadius - kGrooveAxis;
    const auto at = [&](int u) {
        const double along = -24.0 + 12.0 * u;
        return L.to_world(kOffCentre + (side == 0 ? Vec3(along, 2.0, r) : Vec3(-3.0, along, r)));
    };
    subtract_capsule(m, Segment{at(k), at(k + 1)}, kGrooveRadius * L.cell_m);
}

// Every tile contoured at start-up, with coarse group levels; strokes drawn coarse, as the sculpt thread draws them.
struct Session {
    TriDexel model = off_centre_sphere();
    Contourer contourer{model};
    DeferredContour deferral{model.tiles.tiles};
    TileSurfaceCache cache;

    Session() {
        contourer.update(model);
        use_coarse_lod(cache, model, coarse_levels());
        refresh();
        settle(cache);
    }
    void refresh() { refresh_held_tiles(cache, contourer, nullptr, &deferral); }
};

// The nearest hit along -z from above the model at grid column (x, y), on the tiles in and on the finest level of
// every group whose children do not cover it (what a frame draws there at the least and what a pick reads), as a
// grid z; nullopt when the ray meets nothing.
std::optional<double> hit_from_above(const TileSurfaceCache& cache, const Lattice& L, double x, double y) {
    const Vec3 o = L.to_world(Vec3(x, y, 200.0));
    std::optional<double> best;  // metres along the ray
    const auto cast = [&](const TriMesh& mesh, const Aabb& bounds) {
        if (o.x < bounds.lo.x || o.x > bounds.hi.x || o.y < bounds.lo.y || o.y > bounds.hi.y) return;
        for (const auto& tri : mesh.triangles) {
            const Vec3 a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
            // The column's point in the triangle's xy projection, by barycentric weights.
            const double det = (b.y - c.y) * (a.x - c.x) + (c.x - b.x) * (a.y - c.y);
            if (std::abs(det) < 1e-18) continue;
            const double w0 = ((b.y - c.y) * (o.x - c.x) + (c.x - b.x) * (o.y - c.y)) / det;
            const double w1 = ((c.y - a.y) * (o.x - c.x) + (a.x - c.x) * (o.y - c.y)) / det;
            const double w2 = 1.0 - w0 - w1;
            if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
            const double t = o.z - (w0 * a.z + w1 * b.z + w2 * c.z);
            if (t > 0.0 && (!best || t < *best)) best = t;
        }
    };
    for (const TileSurface& t : cache.tiles()) cast(t.mesh, t.bounds_m);
    for (const TileGroupSurface& g : cache.groups())  // a level's ring and skirt reach past the group's box
        if (!g.children_cover && !g.lods.empty()) cast(g.lods.front().mesh, g.lods.front().mesh.bounds());
    if (!best) return std::nullopt;
    return 200.0 - *best / L.cell_m;
}

// Every column over the sphere's +z cap within `half` cells of its axis is hit on the near side: no deeper than the
// groove's floor and a coarse level's error below the sphere, no higher than that error above it. Returns the worst
// depth below the sphere, cells.
double expect_cap_hit_near_side(const TileSurfaceCache& cache, const Lattice& L, const std::string& when) {
    constexpr double kHalf = 28.0, kStep = 2.0;
    // The grooves' floor (deep_cut): kGrooveAxis + kGrooveRadius cells deep along the normal, up to 1.22 times that
    // vertically where the cap slopes most (28 cells off its axis).
    constexpr double kGrooveFloor = 1.25 * (kGrooveAxis + kGrooveRadius);
    constexpr double kCoarseError = 2.0 * (1 << kCoarsest);  // two cells of the coarsest levels' lattice
    double worst = 0.0;
    std::size_t misses = 0, far = 0;
    for (double dx = -kHalf; dx <= kHalf; dx += kStep)
        for (double dy = -kHalf; dy <= kHalf; dy += kStep) {
            const double r2 = kOffCentreRadius * kOffCentreRadius - dx * dx - dy * dy;
            if (r2 < 20.0 * 20.0) continue;
            const double sphere_z = kOffCentre.z + std::sqrt(r2);
            const std::optional<double> z = hit_from_above(cache, L, kOffCentre.x + dx, kOffCentre.y + dy);
            if (!z) {
                ++misses;
                continue;
            }
            worst = std::max(worst, sphere_z - *z);
            if (*z < sphere_z - kGrooveFloor - kCoarseError || *z > sphere_z + kCoarseError) ++far;
        }
    EXPECT_EQ(misses, 0u) << when << ": columns over the cap that meet no surface";
    EXPECT_EQ(far, 0u) << when << ": columns hit off the near side (worst " << worst << " cells below the sphere)";
    return worst;
}

// Per coarsest group, its children: an arrival that changes them regroups it, and its level is dropped.
std::map<std::uint64_t, std::vector<std::uint64_t>> coarsest_children(const TileSurfaceCache& cache) {
    std::map<std::uint64_t, std::vector<std::uint64_t>> out;
    for (const TileGroupSurface& g : cache.groups())
        if (g.depth == kCoarsest) out[g.id] = g.children;
    return out;
}

std::size_t coarsest_waiting(const TileSurfaceCache& cache) {
    std::size_t n = 0;
    for (const TileGroupSurface& g : cache.groups()) n += g.depth == kCoarsest && g.levels_waiting;
    return n;
}

// Two strokes across the +z cap; after each, its hidden tiles arrive a few at a time with no pass between to settle
// the levels, and the second stroke starts before they are all in (its press meets a half-arrived first stroke).
TEST(StrokeArrivals, TheCoarsestLevelsHoldTheWholeSurfaceWhileAStrokesTilesArrive) {
    Session s;
    const Lattice& L = s.model.lattice;
    expect_cap_hit_near_side(s.cache, L, "before the strokes");
    std::size_t arrival_refreshes = 0, coarsest_regrouped_by_arrivals = 0;
    double worst = 0.0;
    for (int side = 0; side < 2; ++side) {
        // The second stroke crosses the first's path, over its hidden and arriving tiles.
        for (int k = 0; k < 4; ++k) {
            const std::string when = "stroke " + std::to_string(side) + " step " + std::to_string(k);
            deep_cut(s.model, k, side);
            s.cache.defer_tiles(s.deferral.defer(s.model));
            s.cache.collect_lods(true);
            s.refresh();
            EXPECT_EQ(coarsest_waiting(s.cache), 0u) << when;
            worst = std::max(worst, expect_cap_hit_near_side(s.cache, L, when));
        }
        for (int batch = 0; batch < (side == 0 ? 6 : 1000) && s.deferral.count() > 0; ++batch) {
            const std::string when = "after stroke " + std::to_string(side) + ", batch " + std::to_string(batch);
            const auto before = coarsest_children(s.cache);
            ASSERT_GT(s.deferral.contour_oldest(s.model, s.contourer, 4), 0u);
            s.refresh();
            ++arrival_refreshes;
            if (coarsest_children(s.cache) != before) ++coarsest_regrouped_by_arrivals;
            EXPECT_EQ(coarsest_waiting(s.cache), 0u) << when;
            worst = std::max(worst, expect_cap_hit_near_side(s.cache, L, when));
        }
    }
    settle(s.cache);
    expect_cap_hit_near_side(s.cache, L, "settled");
    std::printf(
        "[stroke arrivals] %zu refreshes of arrivals only, %zu of them regrouped a coarsest group; deepest hit "
        "%.2f cells below the sphere\n",
        arrival_refreshes, coarsest_regrouped_by_arrivals, worst);
    EXPECT_GT(coarsest_regrouped_by_arrivals, 0u)
        << "no arrival regrouped a coarsest group: the test would not see its level missing";
}

// A bead added in the air, thinner than the coarsest levels' stride, by a stroke drawn coarse: its group's coarse read
// finds no surface and its tile is hidden, so nothing would show it until the stroke's tiles arrive. The group is
// listed as missing a surface (as start-up's are), and contouring the tiles of the listed groups shows it.
TEST(StrokeArrivals, ABeadThinnerThanTheCoarseStrideIsListedAndItsTileContouredFirst) {
    Session s;
    const Lattice& L = s.model.lattice;
    // In the air of the lattice's far corner (the sphere's surface is over 20 cells away), on odd nodes: the rays
    // through it are odd, the coarsest levels read every second one.
    const Vec3 bead(113.0, 113.0, 113.0);
    const double radius_cells = 0.8;
    Sweep add;
    add.op = ToolOp::kUnion;
    add.tool.radius_m = radius_cells * L.cell_m;
    add.path_m = Segment{L.to_world(bead), L.to_world(bead)};
    ASSERT_GT(apply_sweep(s.model, add).rays_changed, 0u);
    s.cache.defer_tiles(s.deferral.defer(s.model));
    s.cache.collect_lods(true);
    s.refresh();
    const int t = 113 / TileGrid::kTileCells;  // the bead's tile, whose cells the sphere does not reach
    const std::uint64_t tile = grid_index({t, t, t}, s.contourer.tile_dims());
    const std::uint64_t group = tile_group_id(kCoarsest, group_index_of({t, t, t}, s.contourer.tile_dims(), kCoarsest));
    const auto bead_drawn = [&] {
        const std::size_t i = index_of(s.cache.tiles(), tile);
        return i < s.cache.tiles().size() && !s.cache.tiles()[i].mesh.triangles.empty();
    };
    ASSERT_FALSE(bead_drawn()) << "the bead's tile is in before its stroke's tiles arrive: nothing to test";
    const std::size_t g = index_of(s.cache.groups(), group);
    ASSERT_LT(g, s.cache.groups().size()) << "no group over the bead's tile";
    ASSERT_TRUE(s.cache.groups()[g].lods.empty() || s.cache.groups()[g].lods.front().mesh.triangles.empty())
        << "the coarse read saw the bead: nothing to test";
    const std::vector<std::uint64_t> missed = s.cache.missed_surface_groups();
    EXPECT_TRUE(std::binary_search(missed.begin(), missed.end(), group)) << "the bead's group is not listed";
    // As the sculpt thread does with the groups a frame asks for and those listed here.
    const WantedRefined n = refine_wanted_groups(missed, s.cache.groups(), s.model, s.contourer, nullptr, &s.deferral,
                                                 1, [] { return true; });
    EXPECT_GT(n.deferred, 0u);
    s.refresh();
    EXPECT_TRUE(bead_drawn()) << "the bead's tile is still not in";
    EXPECT_TRUE(s.cache.missed_surface_groups().empty());
}

}  // namespace
}  // namespace tridex::compute
