// tests/compute/test_scan_convert.cpp - scan conversion against exact answers: lattice-aligned boxes
// ray by ray, a rotated cube and spheres against a brute-force double-precision ray caster, and
// volumes of the shared meshes against their exact mesh volumes.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "compute/mesh/mesh_io.hpp"
#include "core/primitives.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/volume.hpp"
#include "compute/model/workpiece.hpp"
#include "core/error.hpp"

using namespace tridex;
using namespace tridex::compute;

namespace {

constexpr std::size_t kMaxBytes = std::size_t{1} << 31;

// Volume tolerances, as a mean surface offset in cells: |V_dexel - V_mesh| <= offset x surface area.
// The dexel volume is a midpoint-rule sum over h x h ray columns, exact for lattice-aligned faces; on
// curved and slanted surfaces the measured offsets are <= 0.0043 cell for the three-set average and
// <= 0.0093 cell for a single set (see the printed numbers); the tolerances leave a 5x margin.
constexpr double kOffsetTolCells = 0.02;
constexpr double kSingleSetOffsetTolCells = 0.05;

std::string shared_data() {
    const char* d = std::getenv("TRIDEX_SHARED_DATA");
    return d ? d : "../shared/data";
}

/// A lattice of `n` cells per axis, 1 mm cells, origin at an arbitrary non-round point.
Lattice test_lattice(int n) {
    Lattice L;
    L.origin_m = Vec3(0.1, -0.2, 0.3);
    L.cell_m = 0.001;
    L.cells = {n, n, n};
    return L;
}

/// World box of a grid-unit box on lattice L.
Aabb world_box(const Lattice& L, const Vec3& lo_g, const Vec3& hi_g) { return Aabb{L.to_world(lo_g), L.to_world(hi_g)}; }

/// Every ray: enter < exit, sorted, disjoint and not touching.
void expect_ray_invariants(const TriDexel& m) {
    for (const RaySet& s : m.sets)
        for (const auto& ray : s.rays)
            for (std::size_t i = 0; i < ray.size(); ++i) {
                ASSERT_LT(ray[i].enter, ray[i].exit);
                if (i > 0) {
                    ASSERT_LT(ray[i - 1].exit, ray[i].enter);
                }
            }
}

/// Expects every ray of `m` to match the box [lo, hi] (grid units, integer or not): the ray at node
/// (u, v) holds [lo[a], hi[a]] exactly when lo <= u < hi and lo <= v < hi (the perturbed ray at
/// (u + eps, v + eps^2) is inside), and nothing otherwise.
void expect_box_rays(const TriDexel& m, const Vec3& lo, const Vec3& hi) {
    std::size_t filled = 0;
    for (const RaySet& s : m.sets) {
        const int a = s.axis, ua = (a + 1) % 3, va = (a + 2) % 3;
        for (int v = 0; v < s.nv; ++v)
            for (int u = 0; u < s.nu; ++u) {
                const bool inside = lo[ua] <= u && u < hi[ua] && lo[va] <= v && v < hi[va];
                const auto& ray = s.ray(u, v);
                if (!inside) {
                    EXPECT_TRUE(ray.empty()) << "set " << a << " ray " << u << "," << v;
                    continue;
                }
                ++filled;
                ASSERT_EQ(ray.size(), 1u) << "set " << a << " ray " << u << "," << v;
                EXPECT_EQ(ray[0].enter, static_cast<float>(lo[a]));
                EXPECT_EQ(ray[0].exit, static_cast<float>(hi[a]));
            }
    }
    EXPECT_GT(filled, 0u);
}

/// Brute-force reference: the solid intervals of one ray from every triangle in double precision,
/// without snapping. Returns false when the ray passes within `margin` cells of a projected triangle
/// edge (there snapping may legitimately decide the other way), so the caller skips it.
bool reference_ray(const std::vector<Vec3>& g, const TriMesh& mesh, int a, double u, double v, double margin,
                   std::vector<std::pair<double, double>>& out) {
    const int ua = (a + 1) % 3, va = (a + 2) % 3;
    std::vector<std::pair<double, int>> hits;
    for (const auto& t : mesh.triangles) {
        const Vec3 &A = g[t[0]], &B = g[t[1]], &C = g[t[2]];
        auto orient = [&](const Vec3& p, const Vec3& q) { return (q[ua] - p[ua]) * (v - p[va]) - (q[va] - p[va]) * (u - p[ua]); };
        auto edge_len = [&](const Vec3& p, const Vec3& q) { return std::hypot(q[ua] - p[ua], q[va] - p[va]); };
        const double area2 = (B[ua] - A[ua]) * (C[va] - A[va]) - (B[va] - A[va]) * (C[ua] - A[ua]);
        if (area2 == 0.0) continue;
        const double wa = orient(B, C), wb = orient(C, A), wc = orient(A, B);
        const double da = std::abs(wa) / edge_len(B, C), db = std::abs(wb) / edge_len(C, A), dc = std::abs(wc) / edge_len(A, B);
        const bool inside = (wa > 0) == (area2 > 0) && (wb > 0) == (area2 > 0) && (wc > 0) == (area2 > 0);
        if (std::min({da, db, dc}) < margin) {
            // Near an edge: ambiguous only if the point is near the triangle, not merely near the edge's line.
            const double wmin = std::min({wa / area2, wb / area2, wc / area2});
            if (wmin > -0.5) return false;
            continue;
        }
        if (!inside) continue;
        hits.push_back({(wa * A[a] + wb * B[a] + wc * C[a]) / area2, area2 > 0 ? -1 : 1});
    }
    std::sort(hits.begin(), hits.end());
    int w = 0;
    double enter = 0.0;
    for (const auto& [d, s] : hits) {
        const int before = w;
        w += s;
        if (before <= 0 && w > 0) enter = d;
        if (before > 0 && w <= 0) out.push_back({enter, d});
    }
    return true;
}

/// Compares every ray of `m` with the brute-force reference; returns how many rays were compared.
std::size_t compare_with_reference(const TriDexel& m, const TriMesh& mesh_m, double tol_cells) {
    std::vector<Vec3> g;
    for (const Vec3& p : mesh_m.positions) g.push_back(m.lattice.to_grid(p));
    std::size_t compared = 0, skipped = 0;
    for (const RaySet& s : m.sets)
        for (int v = 0; v < s.nv; ++v)
            for (int u = 0; u < s.nu; ++u) {
                std::vector<std::pair<double, double>> ref;
                if (!reference_ray(g, mesh_m, s.axis, u, v, 1e-4, ref)) {
                    ++skipped;
                    continue;
                }
                ++compared;
                const auto& ray = s.ray(u, v);
                EXPECT_EQ(ray.size(), ref.size()) << "set " << s.axis << " ray " << u << "," << v;
                if (ray.size() != ref.size()) continue;
                for (std::size_t i = 0; i < ray.size(); ++i) {
                    EXPECT_NEAR(ray[i].enter, ref[i].first, tol_cells);
                    EXPECT_NEAR(ray[i].exit, ref[i].second, tol_cells);
                }
            }
    EXPECT_LT(skipped, compared / 100 + 1);
    return compared;
}

/// Surface area of a mesh, m^2.
double surface_area(const TriMesh& m) {
    double a = 0.0;
    for (const auto& t : m.triangles)
        a += 0.5 * glm::length(glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]));
    return a;
}

}  // namespace

TEST(ScanConvert, BoxWithFacesBetweenNodesIsExactRayByRay) {
    TriDexel m = TriDexel::empty(test_lattice(16), kMaxBytes);
    const Vec3 lo(2.5, 3.25, 1.75), hi(6.5, 9.25, 5.75);  // 4 x 6 x 4 cells
    scan_convert(box_mesh(world_box(m.lattice, lo, hi)), m);
    expect_box_rays(m, lo, hi);
    expect_ray_invariants(m);
    const double h3 = std::pow(m.lattice.cell_m, 3);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(ray_set_volume_m3(m, a) / h3, 96.0, 1e-9);
    EXPECT_NEAR(dexel_volume_m3(m) / h3, 96.0, 1e-9);
}

TEST(ScanConvert, BoxWithFacesOnNodesIsExactRayByRay) {
    // Rays run through the box's vertices, along its edges and within its faces.
    TriDexel m = TriDexel::empty(test_lattice(16), kMaxBytes);
    const Vec3 lo(2, 3, 1), hi(6, 9, 5);
    scan_convert(box_mesh(world_box(m.lattice, lo, hi)), m);
    expect_box_rays(m, lo, hi);
    expect_ray_invariants(m);
    EXPECT_NEAR(dexel_volume_m3(m) / std::pow(m.lattice.cell_m, 3), 96.0, 1e-9);
}

TEST(ScanConvert, TwoBoxesSharingAFaceMergeIntoOneInterval) {
    // Two closed boxes touching along x = 5: the winding number stays > 0 across the shared face.
    TriDexel m = TriDexel::empty(test_lattice(12), kMaxBytes);
    TriMesh both = box_mesh(world_box(m.lattice, Vec3(2, 2, 2), Vec3(5, 6, 6)));
    const TriMesh right = box_mesh(world_box(m.lattice, Vec3(5, 2, 2), Vec3(9, 6, 6)));
    const auto base = static_cast<std::uint32_t>(both.positions.size());
    both.positions.insert(both.positions.end(), right.positions.begin(), right.positions.end());
    for (auto t : right.triangles) both.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    scan_convert(both, m);
    expect_box_rays(m, Vec3(2, 2, 2), Vec3(9, 6, 6));
}

TEST(ScanConvert, RotatedCubeMatchesBruteForceRays) {
    TriDexel m = TriDexel::empty(test_lattice(40), kMaxBytes);
    const double side = 17.0;  // cells
    TriMesh cube = box_mesh(Aabb{Vec3(-side / 2), Vec3(side / 2)});
    const Mat4 rot = glm::mat4_cast(glm::angleAxis(0.7, glm::normalize(Vec3(1.0, 2.0, 0.5))));
    const Mat4 place = glm::translate(Mat4(1.0), m.lattice.to_world(Vec3(20.3, 19.6, 20.1))) * glm::scale(Mat4(1.0), Vec3(m.lattice.cell_m)) * rot;
    cube = transformed(cube, place);
    scan_convert(cube, m);
    expect_ray_invariants(m);
    const std::size_t compared = compare_with_reference(m, cube, 2e-5);
    EXPECT_GT(compared, 3u * 41 * 41 * 99 / 100);
    const double cells = dexel_volume_m3(m) / std::pow(m.lattice.cell_m, 3);
    std::cout << "[ rotcube  ] volume " << cells << " cells vs " << side * side * side << " (error "
              << cells - side * side * side << " cells, " << (cells / (side * side * side) - 1.0) << " relative)\n";
    EXPECT_NEAR(cells, side * side * side, kOffsetTolCells * 6.0 * side * side);
}

TEST(ScanConvert, IcosphereMatchesBruteForceAndItsMeshVolume) {
    TriDexel m = TriDexel::empty(test_lattice(64), kMaxBytes);
    const double r = 10.3;  // cells
    const TriMesh sphere = icosphere_mesh(m.lattice.to_world(Vec3(32.21, 31.7, 32.45)), r * m.lattice.cell_m, 4);
    scan_convert(sphere, m);
    expect_ray_invariants(m);
    compare_with_reference(m, sphere, 2e-5);
    const double h3 = std::pow(m.lattice.cell_m, 3);
    const double mesh_cells = signed_volume(sphere) / h3, dexel_cells = dexel_volume_m3(m) / h3;
    const double ball_cells = 4.0 / 3.0 * M_PI * r * r * r;
    std::cout << "[ sphere   ] r=" << r << " cells: dexel " << dexel_cells << ", mesh " << mesh_cells << ", 4/3 pi r^3 "
              << ball_cells << " cells; dexel-mesh error " << dexel_cells - mesh_cells << " cells ("
              << (dexel_cells / mesh_cells - 1.0) << " relative)\n";
    // Tolerance: the volume of a 0.02-cell layer over the surface (area in cells^2 x 0.02 cell),
    // about 27 cells^3 here; the Riemann sum over ray columns errs by a fraction of that.
    EXPECT_NEAR(dexel_cells, mesh_cells, kOffsetTolCells * surface_area(sphere) / (m.lattice.cell_m * m.lattice.cell_m));
    // Dirty tiles: the sphere spans cells 21..43 on every axis, tiles of 16 cells: tiles 1 and 2.
    for (int z = 0; z < m.tiles.tiles[2]; ++z)
        for (int y = 0; y < m.tiles.tiles[1]; ++y)
            for (int x = 0; x < m.tiles.tiles[0]; ++x) {
                const bool inner = x >= 1 && x <= 2 && y >= 1 && y <= 2 && z >= 1 && z <= 2;
                EXPECT_EQ(m.tiles.dirty[m.tiles.index(x, y, z)] != 0, inner) << x << "," << y << "," << z;
            }
}

TEST(ScanConvert, IcosphereVolumeOverOffsets) {
    TriDexel blank = TriDexel::empty(test_lattice(64), kMaxBytes);
    const double h3 = std::pow(blank.lattice.cell_m, 3);
    double worst = 0.0, worst_avg = 0.0;
    for (int k = 0; k < 16; ++k) {
        const Vec3 c(32.0 + 0.37 * k - std::floor(0.37 * k), 31.5 + std::fmod(0.61 * k, 1.0), 32.25 + std::fmod(0.23 * k, 1.0));
        const TriMesh sphere = icosphere_mesh(blank.lattice.to_world(c), 10.3 * blank.lattice.cell_m, 4);
        TriDexel m = blank;
        scan_convert(sphere, m);
        const double mesh = signed_volume(sphere) / h3;
        const double area_cells = surface_area(sphere) / (blank.lattice.cell_m * blank.lattice.cell_m);
        for (int a = 0; a < 3; ++a) {
            const double err = std::abs(ray_set_volume_m3(m, a) / h3 - mesh);
            worst = std::max(worst, err);
            EXPECT_LT(err, kSingleSetOffsetTolCells * area_cells) << "centre " << k << " set " << a;
        }
        const double err = std::abs(dexel_volume_m3(m) / h3 - mesh);
        worst_avg = std::max(worst_avg, err);
        EXPECT_LT(err, kOffsetTolCells * area_cells) << "centre " << k;
    }
    std::cout << "[ sphere   ] r=10.3 cells, 16 centres: worst single-set volume error " << worst << " cells, worst average " << worst_avg << " cells\n";
}

TEST(ScanConvert, SharedSphereAndBunnyVolumes) {
    struct Case {
        const char* file;
        int resolution;
    };
    for (const Case& c : {Case{"sphere.off", 64}, Case{"bunny00.off", 128}, Case{"bunny00.off", 256}}) {
        const TriMesh raw = load_closed_mesh(shared_data() + "/meshes/" + c.file);
        const TriMesh mesh = transformed(raw, fit_to_stock(raw.bounds(), Vec3(0.0, 0.1, 0.0), 0.2));
        TriDexel m = TriDexel::empty(Lattice::around(mesh.bounds(), c.resolution), kMaxBytes);
        const auto t0 = std::chrono::steady_clock::now();
        scan_convert(mesh, m);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        expect_ray_invariants(m);
        const double h3 = std::pow(m.lattice.cell_m, 3);
        const double exact = signed_volume(mesh), dexel = dexel_volume_m3(m);
        std::cout << "[ volume   ] " << c.file << " N=" << c.resolution << ": " << ms << " ms, "
                  << m.interval_count() << " intervals, error " << (dexel - exact) / h3 << " cells ("
                  << dexel / exact - 1.0 << " relative, " << (dexel - exact) / (surface_area(mesh) * m.lattice.cell_m)
                  << " cells of mean surface offset)\n";
        EXPECT_LT(std::abs(dexel - exact), kOffsetTolCells * m.lattice.cell_m * surface_area(mesh)) << c.file;
    }
}

TEST(ScanConvert, RefusesNonEmptyModelAndBadMesh) {
    TriDexel m = TriDexel::empty(test_lattice(8), kMaxBytes);
    TriMesh box = box_mesh(world_box(m.lattice, Vec3(2), Vec3(5)));
    scan_convert(box, m);
    EXPECT_THROW(scan_convert(box, m), Error);
    TriDexel fresh = TriDexel::empty(test_lattice(8), kMaxBytes);
    box.triangles[3][1] = 99;
    EXPECT_THROW(scan_convert(box, fresh), Error);
    box.triangles[3][1] = 1;
    box.positions[2].y = NAN;
    EXPECT_THROW(scan_convert(box, fresh), Error);
    EXPECT_EQ(fresh.interval_count(), 0u);
}
