// Tests of `tridex bench --accuracy` (bench/accuracy/bench_accuracy*): the exact reference, the distance queries and a
// tiny run (N = 32, short programs, tridex cpu-1t and cpu, OpenVDB when built in) that writes bench.json with
// sane errors and an all-cores row equal to the one-thread row.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <unistd.h>

#include "bench/accuracy/bench_accuracy.hpp"
#include "bench/accuracy/bench_accuracy_coarse.hpp"
#include "bench/accuracy/bench_accuracy_exact.hpp"
#include "bench/accuracy/bench_accuracy_match.hpp"
#include "bench/accuracy/bench_accuracy_metrics.hpp"
#include "bench/accuracy/bench_accuracy_openvdb.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"

namespace tridex::bench {
namespace {

using namespace accuracy;

TEST(BenchAccuracyExact, BoxAndToolsSdf) {
    const ExactSolid paint(make_program("paint"));
    const double c = 0.5 * (kBoxLoM + kBoxHiM);
    EXPECT_NEAR(paint.sdf(Vec3(c)), -0.05, 1e-12);
    EXPECT_NEAR(paint.sdf(Vec3(c, c, kBoxHiM + 0.01)), 0.01, 1e-12);
    double sigma = 1.0;
    EXPECT_DOUBLE_EQ(paint.volume_m3(1000, sigma), 1e-3);
    EXPECT_EQ(sigma, 0.0);

    Program pocket = make_program("pocket");
    const ExactSolid exact(pocket);
    // The ball centre of the first pass (2 mm above the top face) is removed; the box centre is kept.
    EXPECT_GT(exact.sdf(pocket.moves.front().a), 0.0);
    EXPECT_LT(exact.sdf(Vec3(c)), 0.0);
    const double v = exact.volume_m3(200000, sigma);
    EXPECT_LT(v, 1e-3);
    EXPECT_GT(v, 0.9e-3);
    EXPECT_LT(sigma, 1e-3 * 1e-3);
    for (const Vec3& p : exact.surface_samples(2e5)) EXPECT_LT(std::abs(exact.sdf(p)), 1e-7);
}

TEST(BenchAccuracyExact, FlatEndStadiumAndSegments) {
    Program p = make_program("plunge");
    const ExactSolid exact(p);
    const Move& m = p.moves.front();  // vertical plunge: cylinder of radius 5 mm from the bottom up
    EXPECT_NEAR(exact.sdf(m.b + Vec3(0.0, 0.0, 0.003)), 0.003, 1e-9);  // 3 mm above the plunge's floor, inside the tool
    EXPECT_NEAR(exact.sdf(m.b + Vec3(0.0, 0.0, -0.002)), -0.002, 1e-9);
    for (const auto& s : p.sweeps()) EXPECT_LE(glm::length(s.path_m.b - s.path_m.a), p.segment_m + 1e-12);
    EXPECT_THROW(make_program("nope"), Error);
}

TEST(BenchAccuracyMetrics, PointTriangleAndMeshDistance) {
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    EXPECT_NEAR(point_triangle_distance(Vec3(0.2, 0.2, 0.5), a, b, c), 0.5, 1e-12);
    EXPECT_NEAR(point_triangle_distance(Vec3(-1, 0, 0), a, b, c), 1.0, 1e-12);
    EXPECT_NEAR(point_triangle_distance(Vec3(1, 1, 0), a, b, c), std::sqrt(0.5), 1e-12);
    const TriMesh box = box_mesh(Aabb{Vec3(0.0), Vec3(1.0)});
    const MeshDistance md(box, 0.1);
    EXPECT_NEAR(md.distance(Vec3(0.5, 0.5, 0.6)), 0.4, 1e-12);
    EXPECT_NEAR(md.distance(Vec3(0.5, 0.5, 3.0)), 2.0, 1e-12);
    EXPECT_NEAR(md.distance(Vec3(-1.0, 0.5, 0.5)), 1.0, 1e-12);
}

/// A fresh output folder of this test process under the temp folder: ctest runs tests of this file side by side.
std::string test_out(const std::string& stem) {
    return (std::filesystem::temp_directory_path() / (stem + "_" + std::to_string(::getpid()))).string();
}

class BenchAccuracyTiny : public ::testing::TestWithParam<double> {};

// offset 0: the cube's faces at 3.5 cells; 0.37: lattice shifted (checks the OpenVDB frame follows it).
TEST_P(BenchAccuracyTiny, WritesSaneJson) {
    AccuracyBenchOptions o;
    o.offset_cells = GetParam();
    o.resolutions = {32};
    o.short_programs = true;
    o.gpu = false;
    o.openvdb = openvdb_available();
    o.volume_samples = 200000;
    o.plots = false;
    o.out = test_out("tridex_test_bench_accuracy");
    std::filesystem::remove_all(o.out);
    const std::vector<AccuracyRow> rows = run_accuracy_bench(o);
    std::ifstream in(std::filesystem::path(o.out) / "bench.json");
    ASSERT_TRUE(in.good());
    const nlohmann::json j = nlohmann::json::parse(in);
    ASSERT_TRUE(j.contains("runs"));
    EXPECT_EQ(j["runs"].size(), rows.size());
    EXPECT_EQ(rows.size(), program_names().size() * (o.openvdb ? 3u : 2u));  // tridex cpu-1t, cpu (+ openvdb)
    for (const auto& r : j["runs"]) {
        for (const char* k : {"time_per_segment_s", "contour_s", "volume_error_rel", "mean_error_m", "max_error_m", "hausdorff_m"}) {
            ASSERT_TRUE(r.contains(k)) << k;
            EXPECT_TRUE(std::isfinite(r[k].get<double>())) << k;
            EXPECT_GE(r[k].get<double>(), k == std::string("volume_error_rel") ? -1.0 : 0.0) << k;
        }
        EXPECT_EQ(r["n"], 32);
        EXPECT_GT(r["memory_bytes"].get<double>(), 0.0);
    }
    for (const AccuracyRow& r : rows) {
        SCOPED_TRACE(r.method + " " + r.program);
        EXPECT_GT(r.segments, 0u);
        EXPECT_GT(r.vertices, 0u);
        EXPECT_GT(r.surface_samples, 0u);
        EXPECT_LE(r.mean_error_m, r.max_error_m);
        EXPECT_LT(std::abs(r.volume_error_rel), 0.05);
        if (r.method != "tridex") continue;
        EXPECT_LE(r.max_error_m, std::sqrt(3.0) * r.cell_m);
        EXPECT_LE(r.hausdorff_m, 2.0 * r.cell_m);
        if (r.program == "paint") EXPECT_EQ(r.volume_change_m3, 0.0);
        else if (r.program == "union") EXPECT_GT(r.volume_change_m3, 0.0);
        else EXPECT_LT(r.volume_change_m3, 0.0);
    }
    // The all-cores row: one per program, and the same dexels (so the same volume and mesh) as cpu-1t.
    for (const std::string& prog : program_names()) {
        SCOPED_TRACE(prog);
        const AccuracyRow *one = nullptr, *all = nullptr;
        for (const AccuracyRow& r : rows)
            if (r.method == "tridex" && r.program == prog) {
                if (r.path == "cpu") all = &r;
                if (r.path == "cpu-1t") one = &r;
            }
        ASSERT_NE(one, nullptr);
        ASSERT_NE(all, nullptr);
        EXPECT_EQ(all->segments, one->segments);
        EXPECT_GT(all->time_per_segment_s, 0.0);
        EXPECT_EQ(all->volume_m3, one->volume_m3);
        EXPECT_EQ(all->vertices, one->vertices);
        EXPECT_EQ(all->max_error_m, one->max_error_m);
        EXPECT_EQ(all->hausdorff_m, one->hausdorff_m);
    }
    std::size_t cpu_rows = 0;
    for (const auto& r : j["runs"]) cpu_rows += r["method"] == "tridex" && r["path"] == "cpu";
    EXPECT_EQ(cpu_rows, program_names().size());
}

INSTANTIATE_TEST_SUITE_P(Offsets, BenchAccuracyTiny, ::testing::Values(0.0, 0.37));

TEST(BenchAccuracy, MatchesEveryOpenVdbRunWithTheFastestAsAccurateTridexRun) {
    const auto row = [](const char* method, const char* path, int n, const char* prog, double err, double t) {
        AccuracyRow r;
        r.method = method;
        r.path = path;
        r.n = n;
        r.program = prog;
        r.max_error_m = err;
        r.time_per_segment_s = t;
        return r;
    };
    const std::vector<AccuracyRow> rows{
        row("tridex", "cpu-1t", 64, "a", 4.0, 1.0),  row("tridex", "cpu-1t", 128, "a", 2.0, 3.0),
        row("tridex", "cpu-1t", 256, "a", 1.0, 9.0), row("tridex", "gpu", 64, "a", 4.0, 0.5),
        row("openvdb", "cpu-1t", 64, "a", 2.5, 30.0), row("openvdb", "cpu-1t", 128, "a", 0.5, 90.0),
        row("tridex", "cpu-1t", 64, "b", 1.0, 2.0),  row("openvdb", "cpu-1t", 64, "b", 1.0, 20.0)};
    const std::vector<MatchedRun> m = match_openvdb(rows);
    ASSERT_EQ(m.size(), 5u);  // a: 2 openvdb runs x 2 paths; b: 1 x 1
    // openvdb N = 64 (2.5): cpu-1t's fastest run with error <= 2.5 is N = 128 (3 s): ratio 10.
    EXPECT_EQ(m[0].path, "cpu-1t");
    EXPECT_EQ(m[0].tridex_n, 128);
    EXPECT_DOUBLE_EQ(m[0].ratio, 10.0);
    // gpu has no run as accurate as 2.5: unmatched.
    EXPECT_EQ(m[1].path, "gpu");
    EXPECT_EQ(m[1].tridex_n, 0);
    EXPECT_EQ(m[1].ratio, 0.0);
    // openvdb N = 128 (0.5): no tridex run is as accurate.
    EXPECT_EQ(m[2].tridex_n, 0);
    // b: equal error counts as matched.
    EXPECT_EQ(m[4].program, "b");
    EXPECT_DOUBLE_EQ(m[4].ratio, 10.0);
    EXPECT_EQ(worst_ratio(m, "a", "cpu-1t"), 0.0);
    EXPECT_DOUBLE_EQ(worst_ratio(m, "b", "cpu-1t"), 10.0);
    EXPECT_EQ(worst_ratio(m, "b", "gpu"), -1.0);
}

/// The worst vertex error (cells) of the cpu-1t pocket program alone at `n` cells with the lattice shifted by
/// `offset` cells (no plots, a light error sampling).
double pocket_max_error_cells(int n, double offset) {
    AccuracyBenchOptions o;
    o.resolutions = {n};
    o.programs = {"pocket"};
    o.cpu_all_cores = false;
    o.gpu = false;
    o.openvdb = false;
    o.volume_samples = 100000;
    o.samples_per_cell2 = 0.05;
    o.offset_cells = offset;
    o.plots = false;
    o.out = test_out("tridex_test_bench_accuracy_pocket");
    std::filesystem::remove_all(o.out);
    const std::vector<AccuracyRow> rows = run_accuracy_bench(o);
    std::filesystem::remove_all(o.out);
    if (rows.size() != 1u) throw Error("pocket accuracy run: expected one row");
    return rows[0].max_error_m / rows[0].cell_m;
}

TEST(BenchAccuracy, PocketRimVerticesStayOnTheTopFaceCrease) {
    // The ball-raster pocket at N = 128 with the cube's top face on lattice nodes: the worst vertices sit on
    // the rim where the pocket's wall meets the flat top. The top-face crossings there have a neighbour ray
    // inside the pocket (a crease: no central difference); their exactly flat side gives them the top's
    // normal, which keeps the rim vertices near the crease instead of at their cells' mass points.
    EXPECT_LE(pocket_max_error_cells(128, 0.0), 0.25);
}

TEST(BenchAccuracy, PocketRimAtN64MixesCreaseAndWallNormals) {
    // The ball-raster pocket at N = 64 (ball radius 3 cells, centre one cell above the top face): the rim cells
    // around the passes' ends hold top-face crossings with normals from the crease's flat side beside wall
    // crossings with ordinary normals that make an acute angle with them. Placed with both (the vertex stays
    // within kCreaseResidual of the wall planes), the rim vertices sit on the rim, with the top face on lattice
    // nodes (offset 0) and half a cell off them (offset 0.5).
    EXPECT_LE(pocket_max_error_cells(64, 0.0), 0.1);
    EXPECT_LE(pocket_max_error_cells(64, 0.5), 0.15);
}

TEST(BenchAccuracy, RejectsBadOptions) {
    AccuracyBenchOptions o;
    o.resolutions = {8};
    EXPECT_THROW(run_accuracy_bench(o), Error);
    o.resolutions.clear();
    EXPECT_THROW(run_accuracy_bench(o), Error);
    o.resolutions = {32};
    o.offset_cells = 1.0;
    EXPECT_THROW(run_accuracy_bench(o), Error);
    o.offset_cells = 0.0;
    o.programs = {"no_such_program"};
    EXPECT_THROW(run_accuracy_bench(o), Error);
    o.programs.clear();
    o.coarse_depths = {7};
    EXPECT_THROW(run_accuracy_bench(o), Error);
}

// The coarse group levels at depth 1 of the pocket carved at N = 128 read the rays of the N = 64 lattice: measured
// against the exact solid with the same samples, their worst group error equals the full N = 64 contour's two-sided
// error (the levels hold that contour, tile by tile), and every group box the exact surface crosses has a level.
TEST(BenchAccuracyCoarse, DepthOneLevelsAreAsCloseToTheExactSolidAsAContourAtTheirSpacing) {
    AccuracyBenchOptions o;
    o.resolutions = {64, 128};
    o.programs = {"pocket"};
    o.cpu_all_cores = false;
    o.gpu = false;
    o.openvdb = false;
    o.volume_samples = 100000;
    o.samples_per_cell2 = 0.5;
    o.plots = false;
    o.coarse_depths = {1, 2};
    o.out = test_out("tridex_test_bench_accuracy_coarse");
    std::filesystem::remove_all(o.out);
    const std::vector<AccuracyRow> rows = run_accuracy_bench(o);
    std::ifstream in(std::filesystem::path(o.out) / "bench.json");
    ASSERT_TRUE(in.good());
    const nlohmann::json j = nlohmann::json::parse(in);
    std::filesystem::remove_all(o.out);
    ASSERT_EQ(rows.size(), 2u);
    ASSERT_EQ(j.at("coarse").size(), 4u);  // two N, two depths
    const AccuracyRow& full64 = rows[0];
    ASSERT_EQ(full64.n, 64);
    const nlohmann::json* d1 = nullptr;
    for (const nlohmann::json& r : j.at("coarse"))
        if (r.at("n") == 128 && r.at("depth") == 1) d1 = &r;
    ASSERT_NE(d1, nullptr);
    const double coarse_cell = d1->at("coarse_cell_m").get<double>();
    EXPECT_NEAR(coarse_cell, full64.cell_m, 1e-12);
    EXPECT_NEAR(d1->at("group_max_m").get<double>(), full64.hausdorff_m, 0.01 * coarse_cell);
    EXPECT_GT(d1->at("groups").get<std::size_t>(), 8u);
    EXPECT_EQ(d1->at("samples_without_level").get<std::size_t>(), 0u);
    EXPECT_EQ(d1->at("over_level_estimate").get<std::size_t>(), 0u);  // the pocket's walls are wide: nothing missed
}

// The uncarved box with its faces on lattice nodes: every coarse level lies on the faces, whatever the depth.
TEST(BenchAccuracyCoarse, LevelsOfABoxOnLatticeNodesLieOnItsFaces) {
    const Program paint = make_program("paint");
    const ExactSolid exact(paint);
    compute::Lattice l;
    l.cell_m = kLatticeSideM / 64;
    l.cells = {64, 64, 64};
    compute::TriDexel m = compute::TriDexel::empty(l, std::size_t{1} << 30);
    compute::scan_convert(box_mesh(Aabb{Vec3(kBoxLoM), Vec3(kBoxHiM)}), m);
    const std::vector<Vec3> samples = exact.surface_samples(1.0 / (l.cell_m * l.cell_m));
    const std::vector<CoarseLevelErrors> e = coarse_level_errors(m, exact, samples, {1, 2}, 2);
    ASSERT_EQ(e.size(), 2u);
    for (const CoarseLevelErrors& r : e) {
        EXPECT_GT(r.groups, 0u);
        EXPECT_GT(r.triangles, 0u);
        EXPECT_LT(r.group_max_m, 1e-6 * r.coarse_cell_m) << "depth " << r.depth;
        EXPECT_EQ(r.samples_without_level, 0u);
    }
    EXPECT_EQ(e[0].stride, 2);
    EXPECT_EQ(e[1].stride, 4);
    EXPECT_THROW(coarse_level_errors(m, exact, samples, {0}, 1), Error);
    EXPECT_THROW(coarse_level_errors(m, exact, samples, {1}, 0), Error);
}

}  // namespace
}  // namespace tridex::bench
