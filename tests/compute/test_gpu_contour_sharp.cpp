// tests/compute/test_gpu_contour_sharp.cpp - sharp-feature vertex placement on the GPU (crossing normals
// from neighbouring rays, QEF vertex: shaders/dexel_contour_qef.glsl) against the CPU contourer
// (compute/contour/contour_qef.cpp) bit for bit: boxes with faces on and off lattice nodes, whose edges and
// corners the QEF makes exact, and a box sculpted by flat-end and ball tools (creases and curved faces).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <string>

#include "compute/gpu/gpu_contourer.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/tools/sweep.hpp"
#include "core/primitives.hpp"
#include "gpu/context.hpp"
#include "test_contour_models.hpp"
#include "test_gpu_contour_compare.hpp"

using namespace tridex;
using namespace tridex::compute;
using namespace tridex::compute::testing;

namespace {

/// Largest distance (cells) from a corner of the box [lo, hi] (grid units) to the nearest vertex of the
/// GPU contour: 0 up to rounding when the kernel places sharp corners, about 2/3 cell for mass points.
double gpu_corner_gap(const GpuContourer& gpu, const Lattice& l, const Vec3& lo, const Vec3& hi) {
    const TriMesh m = gpu.download();
    double gap = 0.0;
    for (int c = 0; c < 8; ++c) {
        const Vec3 k((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
        double best = 1e300;
        for (const Vec3& p : m.positions) best = std::min(best, glm::length(l.to_grid(p) - k));
        gap = std::max(gap, best);
    }
    return gap;
}

/// The box [lo, hi] (grid units) scan-converted on a 48^3 lattice (3^3 tiles, the box across tile seams).
TriDexel scanned_box(const Vec3& lo, const Vec3& hi) {
    const Lattice l = cube_lattice(48);
    TriDexel m = TriDexel::empty(l, std::size_t{1} << 32);
    scan_convert(box_mesh(Aabb{l.to_world(lo), l.to_world(hi)}), m);
    return m;
}

/// expect_same_contour, then the GPU contour's box corners: each within `tol` cells of a vertex.
void expect_same_sharp_box(const gpu::Context& ctx, TriDexel& model, const Vec3& lo, const Vec3& hi, const std::string& label) {
    double gap = -1.0;
    expect_same_contour(ctx, model, label, nullptr, [&](const GpuContourer& gpu) { gap = gpu_corner_gap(gpu, model.lattice, lo, hi); });
    std::cout << "[ gpu sharp ] " << label << ": GPU box corner gap " << gap << " cells\n";
    // Float depths of up to 40 cells: rounding ~4e-6 cells (the CPU test's bound).
    EXPECT_GE(gap, 0.0) << label << ": the GPU mesh was not inspected";
    EXPECT_LE(gap, 1e-5) << label;
}

}  // namespace

TEST(GpuContourSharp, BoxesWithFacesOnAndOffLatticeNodesGiveTheCpuMeshAndExactCorners) {
    gpu::Context ctx = gpu::Context::create({});
    {
        // All faces on lattice nodes (crossings at the edge ends; the mass point of a corner cell lies 2/3
        // cell inside, the QEF vertex on the corner).
        const Vec3 lo(10.0, 12.0, 9.0), hi(40.0, 30.0, 37.0);
        TriDexel on_nodes = scanned_box(lo, hi);
        expect_same_sharp_box(ctx, on_nodes, lo, hi, "box faces on nodes");
        // One face (x = 40.4) off the nodes, the others on them.
        const Vec3 hi_off(40.4, 30.0, 37.0);
        TriDexel one_off = scanned_box(lo, hi_off);
        expect_same_sharp_box(ctx, one_off, lo, hi_off, "box one face off nodes");
        // Every face off the nodes, exact chords written into the rays.
        const Vec3 lo2(10.3, 12.6, 9.2), hi2(40.7, 30.1, 37.55);
        TriDexel off = empty_model(cube_lattice(48));
        fill_rays(off, [&](int a, int u, int v) { return box_chord(lo2, hi2, a, u, v); });
        expect_same_sharp_box(ctx, off, lo2, hi2, "box faces off nodes");
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuContourSharp, BoxSculptedByFlatEndAndBallToolsGivesTheCpuMesh) {
    gpu::Context ctx = gpu::Context::create({});
    {
        const Lattice L = cube_lattice(64);
        TriDexel model = TriDexel::empty(L, std::size_t{1} << 32);
        scan_convert(box_mesh(Aabb{L.to_world(Vec3(8.0, 8.0, 8.0)), L.to_world(Vec3(56.0, 50.5, 44.0))}), model);
        // Flat-end pockets and slots (vertical walls meeting flat floors: creases), ball grooves, unions
        // and paint strokes across tile seams.
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> pos(10.0, 54.0), unit(0.0, 1.0);
        for (int i = 0; i < 24; ++i) {
            Sweep s;
            const double pick = unit(rng);
            s.op = pick < 0.6 ? ToolOp::kSubtract : pick < 0.85 ? ToolOp::kUnion : ToolOp::kPaint;
            s.material = static_cast<std::uint8_t>(1 + i % 5);
            const bool flat = i % 3 != 2;
            s.tool = SweepTool{flat ? ToolKind::kFlatEnd : ToolKind::kBall, (2.0 + 5.0 * unit(rng)) * L.cell_m, 6.0 * L.cell_m};
            // Flat ends mostly along the lattice axes (axis-aligned floors and walls), some tilted.
            s.axis = i % 4 == 0 ? Vec3(unit(rng) - 0.5, unit(rng) - 0.5, 1.0) : Vec3(0.0, 0.0, 1.0);
            const Vec3 a = L.to_world(Vec3(pos(rng), pos(rng), i % 2 ? 44.0 - 2.0 * unit(rng) : pos(rng)));
            s.path_m = Segment{a, a + Vec3(unit(rng) - 0.5, unit(rng) - 0.5, 0.0) * (30.0 * L.cell_m)};
            apply_sweep(model, s);
        }
        std::fill(model.tiles.dirty.begin(), model.tiles.dirty.end(), std::uint8_t{1});
        const MeshDiff d = expect_same_contour(ctx, model, "sculpted box");
        EXPECT_GT(d.cpu_triangles, 10000u);
        // The GPU matched the CPU on vertices from every QEF branch: corners (no direction dropped), faces
        // and edges (truncated), minimisers outside their cell (minimised again on its boundary).
        const ContourStats& q = d.cpu_stats;
        EXPECT_GT(q.qef_vertices - q.qef_truncated, 0u) << "no corner vertex";
        EXPECT_GT(q.qef_truncated, 0u);
        EXPECT_GT(q.qef_clamped, 0u);
        EXPECT_EQ(q.qef_rejected, 0u);
        EXPECT_GT(q.vertices - q.qef_vertices, 0u) << "no vertex without a normal (mass point)";
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuContourSharp, SplitFacesInASheetBetweenTwoBallCutsGiveTheCpuMesh) {
    // A box carved by two large balls (radius 60 cells) that leave a sheet 0.6 to 0.95 cells thick at about 45
    // degrees to x and y (ContourCuts.SplitFaceInASheetLiesOnAWall's models): split faces whose segments join
    // crossings on the sheet's two walls (nearly opposite normals). Lattice phases until some face is split.
    gpu::Context ctx = gpu::Context::create({});
    {
        std::size_t splits = 0;
        for (int k = 0; k < 24 && splits == 0; ++k) {
            const int i = k % 8;
            const double w = k < 8 ? 0.95 : k < 16 ? 0.75 : 0.6, s = 0.137 * i;
            const Vec3 lo(8.0), hi(40.0), c(24.0 + s, 24.0 + 0.6 * s, 24.0 + 0.3 * s);
            const Vec3 n = glm::normalize(Vec3(1.0, 0.8 + 0.05 * i, 0.1));
            const Vec3 centres[2] = {c - (60.0 + 0.5 * w) * n, c + (60.0 + 0.5 * w) * n};
            TriDexel model = empty_model(cube_lattice(48));
            fill_rays(model, [&](int a, int u, int v) {
                const int b = (a + 1) % 3, cc = (a + 2) % 3;
                if (u < lo[b] || u > hi[b] || v < lo[cc] || v > hi[cc]) return std::vector<Interval>{};
                std::vector<std::pair<double, double>> spans{{lo[a], hi[a]}};
                for (const Vec3& q : centres) {
                    const double du = u - q[b], dv = v - q[cc], d2 = du * du + dv * dv;
                    if (d2 >= 3600.0) continue;
                    const double half = std::sqrt(3600.0 - d2);
                    subtract_span(spans, q[a] - half, q[a] + half);
                }
                return spans_to_intervals(spans);
            });
            const MeshDiff d = expect_same_contour(ctx, model, "sheet between two ball cuts " + std::to_string(k));
            splits += d.cpu_stats.split_faces;
        }
        EXPECT_GT(splits, 0u) << "no split face in the sheets";
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuContourSharp, ThirdBallFillingACreaseCornerGivesTheCpuMesh) {
    // ContourCuts.ThirdBallFillingACreaseCornerKeepsTheVertexOnIt's models: crease vertices placed again with a
    // face-adjacent cell's tangent plane (the corner fill), which reads rays beyond the tile's occupancy block.
    gpu::Context ctx = gpu::Context::create({});
    for (const BallsOnABox& k : balls_filling_crease_corners()) {
        const Vec3 lo(6.0), hi(42.0, 42.0, k.top);
        TriDexel model = empty_model(cube_lattice(48));
        fill_rays(model, [&](int a, int u, int v) { return box_plus_balls_chord(lo, hi, k.balls, a, u, v); });
        expect_same_contour(ctx, model, "balls on a box, top " + std::to_string(k.top));
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuContourSharp, FinCrestThinnerThanACellGivesTheCpuMesh) {
    // ContourCuts.FinCrestThinnerThanACellKeepsItsVertexOnAWall's models: components whose normals all came from
    // one-sided slopes borrow when a face-adjacent cell's normal contradicts their own (contour::kBorrowWrongCos).
    gpu::Context ctx = gpu::Context::create({});
    for (const FinCrestModel& k : fin_crests_between_ball_cuts()) {
        const Vec3 lo(8.0), hi(40.0, 40.0, k.top);
        TriDexel model = empty_model(cube_lattice(48));
        fill_rays(model, [&](int a, int u, int v) { return box_minus_balls_chord(lo, hi, k.balls, a, u, v); });
        expect_same_contour(ctx, model, "fin crest, top " + std::to_string(k.top));
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuContourSharp, AirGapBetweenTwoAddedBallsGivesTheCpuMesh) {
    // ContourCuts.AirGapBetweenTwoAddedBallsKeepsItsVertexOnAWall's models: components without a normal borrow the
    // face-adjacent cells' crossing normals (contour::kBorrowReach) and keep one wall's.
    gpu::Context ctx = gpu::Context::create({});
    for (const AirGapModel& k : air_gaps_between_added_balls()) {
        const Vec3 lo(6.0), hi(42.0, 42.0, k.model.top);
        TriDexel model = empty_model(cube_lattice(48));
        fill_rays(model, [&](int a, int u, int v) { return box_plus_balls_chord(lo, hi, k.model.balls, a, u, v); });
        expect_same_contour(ctx, model, "air gap, top " + std::to_string(k.model.top));
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}
