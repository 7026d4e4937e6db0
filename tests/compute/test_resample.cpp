// Tests of re-sampling a model onto a finer or coarser lattice (compute/tools/model_resample.hpp) on analytic
// solids: the lattice it picks, volume and surface kept through N -> N' -> N, materials, identity, refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "compute/contour/surface_move.hpp"
#include "compute/model/volume.hpp"
#include "compute/tools/model_resample.hpp"
#include "core/error.hpp"
#include "resample_models.hpp"
#include "tdx_test_models.hpp"

namespace tridex::compute {
namespace {

using namespace resample_test;

constexpr std::size_t kBytes = std::size_t{1} << 30;
constexpr int kN = 48;                               // cells along the longest axis of the test lattice
const Aabb kBox{Vec3(-0.05), Vec3(0.05)};            // the workpiece box, m
const Lattice kLattice = Lattice::around(kBox, kN);  // h = 0.1 m / 44 = 2.27 mm
constexpr double kRadius = 0.04;                     // the ball's radius, m (17.6 cells at kN)
const Vec3 kCentre(0.0011, -0.0007, 0.0004);         // off the nodes, so no ray is tangent by symmetry

/// Prints one measured line (the figures docs/resample.md quotes).
void report(const std::string& what, const ResampleStats& s, double error_m) {
    std::printf(
        "[ measure  ] %s: N %d -> %d, volume %.6g -> %.6g m^3 (%+.4f%%), move %.3g m = %.3f coarse cells, "
        "floor %.3f, analytic error %.3g m = %.3f coarse cells, rays copied %zu blended %zu field %zu\n",
        what.c_str(), s.resolution_before, s.resolution_after, s.volume_before_m3, s.volume_after_m3,
        100.0 * (s.volume_after_m3 - s.volume_before_m3) / s.volume_before_m3, s.max_surface_move_m,
        s.max_surface_move_cells, s.surface_move_floor_m / std::max(s.cell_before_m, s.cell_after_m), error_m,
        error_m / std::max(s.cell_before_m, s.cell_after_m), s.rays_copied, s.rays_blended, s.rays_field);
}

TEST(ResampledLattice, CoversTheSameBoxWithTheCoarseNodesOnTheFineOnes) {
    const Lattice fine = resampled_lattice(kLattice, 2 * kN);
    EXPECT_EQ(lattice_resolution(fine), 2 * kN);
    EXPECT_EQ(fine.cell_m, kLattice.cell_m / 2.0);
    EXPECT_EQ(fine.origin_m, kLattice.origin_m);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(fine.cells[a], 2 * kLattice.cells[a]);
    const Lattice back = resampled_lattice(fine, kN);  // bit for bit the lattice it came from
    EXPECT_EQ(back.origin_m, kLattice.origin_m);
    EXPECT_EQ(back.cell_m, kLattice.cell_m);
    EXPECT_EQ(back.cells, kLattice.cells);
    const Lattice odd = resampled_lattice(kLattice, 72);  // 3/2: same box, centred, within one new cell
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(odd.bounds().centre()[a], kLattice.bounds().centre()[a], 1e-12);
        EXPECT_GE(odd.bounds().size()[a], kLattice.bounds().size()[a] - 1e-12);
        EXPECT_LT(odd.bounds().size()[a], kLattice.bounds().size()[a] + odd.cell_m);
    }
}

TEST(Resample, SameResolutionIsABitExactCopy) {
    const TriDexel m = tdx_test::sculpted_sphere(40, 12, 7);
    ResampleStats s;
    const TriDexel r = resample_model(m, lattice_resolution(m.lattice), kBytes, &s);
    EXPECT_TRUE(s.identical);
    EXPECT_EQ(s.volume_before_m3, s.volume_after_m3);
    tdx_test::expect_identical(m, r);
}

TEST(Resample, SculptedModelDoubledAndBackIsBitExact) {
    // Several intervals per ray, six materials, a lattice longest along y (40 x 43 x 38 cells).
    const TriDexel m = tdx_test::sculpted_sphere(40, 12, 7);
    const int n = lattice_resolution(m.lattice);
    ASSERT_EQ(n, 43);
    const TriDexel back = resample_model(resample_model(m, 2 * n, kBytes), n, kBytes);
    TriDexel dirty = m;  // a resampled model has every tile dirty
    std::fill(dirty.tiles.dirty.begin(), dirty.tiles.dirty.end(), TileGrid::kWhole);
    tdx_test::expect_identical(back, dirty);
}

TEST(Resample, SculptedModelThreeHalvesAndBackKeepsVolumeAndMaterials) {
    const TriDexel m = tdx_test::sculpted_sphere(40, 12, 7);
    ResampleStats there, back;
    const TriDexel x = resample_model(m, 64, kBytes, &there);
    const TriDexel y = resample_model(x, 43, kBytes, &back);
    measure_surface_move(m, x, there);
    measure_surface_move(x, y, back);
    report("sculpted x1.5", there, 0.0);
    report("sculpted x1.5 back", back, 0.0);
    // Thin slivers of the random strokes: a coarser lattice loses some, and the model's own ends lie up to two cells
    // from its contour there (the measure's floor), so the moves are bounded above that floor.
    EXPECT_NEAR(back.volume_after_m3, there.volume_before_m3, 0.015 * there.volume_before_m3);
    for (const ResampleStats* s : {&there, &back}) {
        const double floor_cells = s->surface_move_floor_m / std::max(s->cell_before_m, s->cell_after_m);
        EXPECT_LT(s->max_surface_move_cells, floor_cells + 0.5);
    }
    // Each end back at N has the material of the nearest end of the model it came from (all but a few, at the
    // borders of painted patches).
    std::vector<std::pair<Vec3, std::uint8_t>> ends;
    for_each_end(m, [&](const Vec3& p, std::uint8_t mat) { ends.emplace_back(p, mat); });
    std::size_t same = 0, total = 0;
    for_each_end(y, [&](const Vec3& p, std::uint8_t mat) {
        double best = 1e300;
        std::uint8_t nearest = 0;
        for (const auto& [q, qm] : ends)
            if (glm::dot(p - q, p - q) < best) best = glm::dot(p - q, p - q), nearest = qm;
        ++total;
        same += nearest == mat ? 1 : 0;
    });
    std::printf("[ measure  ] sculpted x1.5 back: %zu of %zu ends keep the nearest old end's material\n", same, total);
    EXPECT_GT(static_cast<double>(same), 0.95 * static_cast<double>(total));  // measured 0.971
}

TEST(Resample, BallDoubledAndBackIsBitExactAndTheFineModelFollowsTheBall) {
    const Shape shape = ball(kCentre, kRadius);
    const TriDexel m = build(kLattice, shape);
    ResampleStats up, down;
    const TriDexel fine = resample_model(m, 2 * kN, kBytes, &up);
    const TriDexel back = resample_model(fine, kN, kBytes, &down);
    measure_surface_move(m, fine, up);
    measure_surface_move(fine, back, down);
    report("ball x2", up, max_error_m(fine, shape));
    report("ball x2 back", down, max_error_m(back, shape));
    tdx_test::expect_identical(back, [&] {  // the same rays; the tiles are all dirty after a resample
        TriDexel d = m;
        std::fill(d.tiles.dirty.begin(), d.tiles.dirty.end(), TileGrid::kWhole);
        return d;
    }());
    const double exact = 4.0 / 3.0 * std::numbers::pi * kRadius * kRadius * kRadius;
    EXPECT_NEAR(up.volume_after_m3, exact, 0.003 * exact);  // within 0.3 %
    EXPECT_LT(up.max_surface_move_cells, 0.1);
    EXPECT_LT(max_error_m(fine, shape), 0.1 * kLattice.cell_m);  // a tenth of a coarse cell
}

/// The bounds a round trip N -> mid -> N must keep.
struct Bounds {
    double volume_mid = 0.0;    ///< |volume at mid - analytic volume| / analytic volume
    double volume_round = 0.0;  ///< |volume back at N - volume before| / analytic volume
    double move_cells = 0.0;    ///< largest surface move of either step, coarse cells
    double error_cells = 0.0;   ///< largest distance of an end back at N from the analytic surface, coarse cells
};

/// Re-samples `m` (of `shape`, analytic volume `exact`) to `mid` and back and checks `b`.
void round_trip(const std::string& what, const TriDexel& m, const Shape& shape, int mid, double exact,
                const Bounds& b) {
    ResampleStats there, back;
    const TriDexel x = resample_model(m, mid, kBytes, &there);
    const TriDexel y = resample_model(x, kN, kBytes, &back);
    measure_surface_move(m, x, there);
    measure_surface_move(x, y, back);
    report(what, there, max_error_m(x, shape));
    report(what + " back", back, max_error_m(y, shape));
    EXPECT_EQ(y.lattice.cells, m.lattice.cells);
    EXPECT_NEAR(there.volume_after_m3, exact, b.volume_mid * exact);
    EXPECT_NEAR(back.volume_after_m3, there.volume_before_m3, b.volume_round * exact);
    EXPECT_LT(there.max_surface_move_cells, b.move_cells);
    EXPECT_LT(back.max_surface_move_cells, b.move_cells);
    const double coarse = std::max(there.cell_before_m, there.cell_after_m);
    EXPECT_LT(max_error_m(y, shape), b.error_cells * coarse);
    EXPECT_GT(there.rays_blended + back.rays_blended, 0u);
}

const double kBallVolume = 4.0 / 3.0 * std::numbers::pi * kRadius * kRadius * kRadius;
const Vec3 kBoxLo(-0.031, -0.022, -0.0137), kBoxHi(0.0287, 0.0191, 0.0333);  // off the nodes
const double kBoxVolume = (kBoxHi.x - kBoxLo.x) * (kBoxHi.y - kBoxLo.y) * (kBoxHi.z - kBoxLo.z);

TEST(Resample, BallThreeHalvesAndBackKeepsVolumeAndSurface) {
    const Shape shape = ball(kCentre, kRadius);
    round_trip("ball x1.5", build(kLattice, shape), shape, 72, kBallVolume, {0.004, 0.004, 0.1, 0.1});
}

TEST(Resample, BallHalvedAndBackKeepsVolumeAndSurface) {
    const Shape shape = ball(kCentre, kRadius);
    round_trip("ball x0.5", build(kLattice, shape), shape, kN / 2, kBallVolume, {0.002, 0.012, 0.2, 0.15});
}

TEST(Resample, BoxThreeHalvesAndBackKeepsVolumeAndSurface) {
    const Shape shape = box(kBoxLo, kBoxHi);
    round_trip("box x1.5", build(kLattice, shape), shape, 72, kBoxVolume, {0.001, 0.001, 0.75, 0.1});
}

TEST(Resample, BoxHalvedAndBackKeepsVolumeAndSurface) {
    const Shape shape = box(kBoxLo, kBoxHi);
    round_trip("box x0.5", build(kLattice, shape), shape, kN / 2, kBoxVolume, {0.002, 0.003, 0.5, 0.1});
}

TEST(Resample, TwoMaterialsStayWhereTheyWere) {
    // Material 3 above the plane z = 0.005 m, material 1 below it.
    const auto side = [](const Vec3& p) { return static_cast<std::uint8_t>(p.z > 0.005 ? 3 : 1); };
    const TriDexel m = build(kLattice, ball(kCentre, kRadius), side);
    for (const int n : {72, kN / 2}) {
        const TriDexel r = resample_model(m, n, kBytes);
        const double reach =
            1.5 * std::max(kLattice.cell_m, r.lattice.cell_m);  // ends this near the plane may go either way
        std::size_t wrong = 0, ends = 0, threes = 0;
        for_each_end(r, [&](const Vec3& p, std::uint8_t mat) {
            ++ends;
            threes += mat == 3 ? 1 : 0;
            if (std::fabs(p.z - 0.005) > reach && mat != side(p)) ++wrong;
        });
        EXPECT_GT(ends, 0u);
        EXPECT_GT(threes, 0u);
        EXPECT_LT(threes, ends);
        EXPECT_EQ(wrong, 0u) << "N' = " << n;
    }
}

TEST(Resample, RefusesALatticeThatDoesNotFitNamingTheMemory) {
    const TriDexel m = build(kLattice, ball(kCentre, kRadius));
    try {
        resample_model(m, 4096, std::size_t{64} << 20);
        FAIL() << "no error";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("resolution 4096"), std::string::npos) << msg;
        EXPECT_NE(msg.find("MiB, more than the 64 MiB available"), std::string::npos) << msg;
    }
}

TEST(Resample, RefusesAResolutionOutOfRange) {
    const TriDexel m = build(kLattice, ball(kCentre, kRadius));
    EXPECT_THROW(resample_model(m, kResampleMinResolution - 1, kBytes), Error);
    EXPECT_THROW(resample_model(m, kResampleMaxResolution + 1, kBytes), Error);
}

TEST(ResampleSurfaceMove, MeasuresAGrownBallInMetres) {
    const TriDexel a = build(kLattice, ball(kCentre, kRadius));
    const TriDexel b = build(resampled_lattice(kLattice, 72), ball(kCentre, kRadius + kLattice.cell_m));
    const double move = surface_move_m(a, b);
    std::printf("[ measure  ] ball grown by one cell: move %.4f cells\n", move / kLattice.cell_m);
    EXPECT_NEAR(move, kLattice.cell_m, 0.2 * kLattice.cell_m);
    EXPECT_LT(surface_move_m(a, a), 0.1 * kLattice.cell_m);
}

}  // namespace
}  // namespace tridex::compute
