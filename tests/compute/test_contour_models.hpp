// tests/compute/test_contour_models.hpp - analytic and random tri-dexel models for the contouring tests
// (rays filled directly, without scan conversion), and mesh checks shared by those tests.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "compute/model/tridexel.hpp"
#include "compute/tools/boolean.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::compute::testing {

/// A cubic lattice of `cells`^3 cells of 1 mm with its origin away from zero (m).
inline Lattice cube_lattice(int cells) {
    Lattice l;
    l.origin_m = Vec3(0.25, -0.125, 0.0625);
    l.cell_m = 1e-3;
    l.cells = {cells, cells, cells};
    return l;
}

/// An empty model on `l` with every tile dirty.
inline TriDexel empty_model(const Lattice& l) {
    TriDexel m = TriDexel::empty(l, std::size_t{1} << 32);
    std::fill(m.tiles.dirty.begin(), m.tiles.dirty.end(), std::uint8_t{1});
    return m;
}

/// Grid position of point (t along axis a) on ray (u, v) of set a.
inline Vec3 ray_point(int a, int u, int v, double t) {
    Vec3 p;
    p[a] = t;
    p[(a + 1) % 3] = u;
    p[(a + 2) % 3] = v;
    return p;
}

/// Fills every ray of the three sets with chord(a, u, v) (sorted, disjoint intervals in grid units).
inline void fill_rays(TriDexel& m, const std::function<std::vector<Interval>(int, int, int)>& chord) {
    for (int a = 0; a < 3; ++a) {
        RaySet& s = m.sets[a];
        for (int v = 0; v < s.nv; ++v)
            for (int u = 0; u < s.nu; ++u) s.ray(u, v) = chord(a, u, v);
    }
}

/// Exact chord of the sphere (centre c, radius r, grid units) along ray (u, v) of set a.
inline std::vector<Interval> sphere_chord(const Vec3& c, double r, int a, int u, int v) {
    const double du = u - c[(a + 1) % 3], dv = v - c[(a + 2) % 3];
    const double d2 = du * du + dv * dv;
    if (d2 >= r * r) return {};
    const double half = std::sqrt(r * r - d2);
    return {Interval{static_cast<float>(c[a] - half), static_cast<float>(c[a] + half)}};
}

/// The sphere of the coarse-level tests: centre off the lattice's nodes (grid units on a 128-cell cube lattice) and
/// radius, cells.
inline const Vec3 kOffCentre(64.31, 63.83, 64.07);
inline constexpr double kOffCentreRadius = 48.6;

/// That sphere on a 128-cell cube lattice, every tile dirty.
inline TriDexel off_centre_sphere() {
    TriDexel m = empty_model(cube_lattice(128));
    fill_rays(m, [](int a, int u, int v) { return sphere_chord(kOffCentre, kOffCentreRadius, a, u, v); });
    return m;
}

/// Cut k (0, 1, ...) of a groove across off_centre_sphere()'s +z cap (`side` 0) or its -y side (`side` 1): a capsule
/// 6 cells in radius, each cut 12 cells on from the last.
inline void groove_cut(TriDexel& m, int k, int side = 0) {
    const Lattice& L = m.lattice;
    const double r = kOffCentreRadius - 4.0;
    const auto at = [&](double u) {
        return L.to_world(kOffCentre +
                          (side == 0 ? Vec3(-30.0 + 12.0 * u, 8.0 * u, r) : Vec3(-30.0 + 12.0 * u, -r, 6.0 * u)));
    };
    subtract_capsule(m, Segment{at(k), at(k + 1)}, 6.0 * L.cell_m);
}

/// Exact chord of the axis-aligned box [lo, hi] (grid units) along ray (u, v) of set a.
inline std::vector<Interval> box_chord(const Vec3& lo, const Vec3& hi, int a, int u, int v) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    if (u <= lo[b] || u >= hi[b] || v <= lo[c] || v >= hi[c]) return {};
    return {Interval{static_cast<float>(lo[a]), static_cast<float>(hi[a])}};
}

/// Deterministic pseudo-random number in (0.05, 0.95) from integers (a hash, so unchanged run ends of an
/// edited model keep their exact positions).
inline double jitter(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    x ^= x >> 31;
    return 0.05 + 0.9 * static_cast<double>(x >> 11) / static_cast<double>(std::uint64_t{1} << 53);
}

/// Ray (u, v) of set a for a node occupancy `inside(i, j, k)`: each run of inside nodes i0..i1 becomes
/// [i0 - s, i1 + s'] with s, s' in (0.05, 0.95) from jitter(), so all three ray sets agree on every
/// node (node x inside iff enter <= x < exit) and every crossing lies on its edge.
inline std::vector<Interval> voxel_ray(const std::function<bool(int, int, int)>& inside, int n_nodes, int a, int u,
                                       int v) {
    std::vector<Interval> ray;
    auto at = [&](int t) {
        const Vec3 p = ray_point(a, u, v, t);
        return inside(static_cast<int>(p.x), static_cast<int>(p.y), static_cast<int>(p.z));
    };
    const std::uint64_t base = ((static_cast<std::uint64_t>(a) * 4096 + static_cast<std::uint64_t>(u)) * 4096 +
                                static_cast<std::uint64_t>(v)) * 4096;
    for (int t = 0; t < n_nodes;) {
        if (!at(t)) {
            ++t;
            continue;
        }
        const int t0 = t;
        while (t < n_nodes && at(t)) ++t;
        const int t1 = t - 1;
        ray.push_back(Interval{static_cast<float>(t0 - jitter((base + t0) * 2)),
                               static_cast<float>(t1 + jitter((base + t1) * 2 + 1))});
    }
    return ray;
}

/// Random voxel set on a cube lattice of `cells`: interior nodes (1 .. cells - 1) inside with probability
/// `density` (seeded by `seed`); the rays of all three sets are built from it, so they agree on every node.
inline TriDexel random_voxels(int cells, double density, unsigned seed) {
    const int n = cells + 1;
    std::vector<std::uint8_t> occ(static_cast<std::size_t>(n) * n * n, 0);
    std::mt19937 rng(seed);
    std::bernoulli_distribution coin(density);
    for (int k = 1; k < cells; ++k)
        for (int j = 1; j < cells; ++j)
            for (int i = 1; i < cells; ++i) occ[i + n * (j + static_cast<std::size_t>(n) * k)] = coin(rng) ? 1 : 0;
    const auto inside = [&](int i, int j, int k) { return occ[i + n * (j + static_cast<std::size_t>(n) * k)] != 0; };
    TriDexel m = empty_model(cube_lattice(cells));
    fill_rays(m, [&](int a, int u, int v) { return voxel_ray(inside, n, a, u, v); });
    return m;
}

/// Lists for every vertex the directed link edges (b -> c for each triangle (v, b, c)) and checks they
/// form one single cycle: no pinched vertex (two fans meeting at one point). Returns the number of
/// vertices whose link is not one cycle (0 for a closed oriented 2-manifold); unused vertices count too.
inline std::size_t pinched_vertices(const TriMesh& m) {
    std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> link(m.positions.size());
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) link[t[k]].push_back({t[(k + 1) % 3], t[(k + 2) % 3]});
    std::size_t bad = 0;
    for (auto& l : link) {
        if (l.size() < 3) {
            ++bad;
            continue;
        }
        std::map<std::uint32_t, std::uint32_t> next;
        bool ok = true;
        for (const auto& [b, c] : l) ok = ok && next.emplace(b, c).second;
        if (!ok) {
            ++bad;
            continue;
        }
        std::uint32_t cur = l.front().first;
        std::size_t steps = 0;
        do {
            const auto it = next.find(cur);
            if (it == next.end()) break;
            cur = it->second;
            ++steps;
        } while (cur != l.front().first && steps <= l.size());
        if (cur != l.front().first || steps != l.size()) ++bad;
    }
    return bad;
}

/// Expects a closed, consistently oriented 2-manifold without degenerate triangles or pinched vertices.
inline void expect_closed_manifold(const TriMesh& m) {
    const EdgeStats s = edge_stats(m);
    EXPECT_GT(m.triangles.size(), 0u);
    EXPECT_EQ(s.boundary_edges, 0u);
    EXPECT_EQ(s.nonmanifold_edges, 0u);
    EXPECT_EQ(s.misoriented_edges, 0u);
    EXPECT_EQ(s.degenerate_triangles, 0u);
    EXPECT_EQ(pinched_vertices(m), 0u);
    // Closed 2-manifold: every edge in exactly two triangles, so 3T = 2E.
    EXPECT_EQ(3 * m.triangles.size(), 2 * s.edges);
}

/// Removes the span [e0, e1] (grid units along a ray) from the sorted disjoint `spans`, dropping empty pieces.
inline void subtract_span(std::vector<std::pair<double, double>>& spans, double e0, double e1) {
    std::vector<std::pair<double, double>> next;
    for (const auto& [s0, s1] : spans) {
        if (e0 > s0) next.push_back({s0, std::min(s1, e0)});
        if (e1 < s1) next.push_back({std::max(s0, e1), s1});
    }
    spans.clear();
    for (const auto& s : next)
        if (s.first < s.second) spans.push_back(s);
}

/// The spans as a ray's intervals (float grid units).
inline std::vector<Interval> spans_to_intervals(const std::vector<std::pair<double, double>>& spans) {
    std::vector<Interval> out;
    for (const auto& [s0, s1] : spans) out.push_back(Interval{static_cast<float>(s0), static_cast<float>(s1)});
    return out;
}

/// A ball cut out of a box (grid units).
struct CutBall {
    Vec3 c;
    double r;
};

/// Exact chords of ray (u, v) of set a through the box [lo, hi] minus the balls (grid units).
inline std::vector<Interval> box_minus_balls_chord(const Vec3& lo, const Vec3& hi, const std::vector<CutBall>& balls,
                                                   int a, int u, int v) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    if (u < lo[b] || u > hi[b] || v < lo[c] || v > hi[c]) return {};
    std::vector<std::pair<double, double>> spans{{lo[a], hi[a]}};
    for (const CutBall& ball : balls) {
        const double du = u - ball.c[b], dv = v - ball.c[c], d2 = du * du + dv * dv;
        if (d2 >= ball.r * ball.r) continue;
        const double half = std::sqrt(ball.r * ball.r - d2);
        subtract_span(spans, ball.c[a] - half, ball.c[a] + half);
    }
    return spans_to_intervals(spans);
}

/// Two balls cut out of the box [8, 40]^2 x [8, top] on a 48^3 lattice, their centres above the top face z = top
/// (off the nodes) on either side of the line y = crest.y, leaving a fin between them along x whose top is thinner
/// than a cell (0.2-0.7 cells), its walls tilted 10-40 degrees from the vertical.
struct FinCrestModel {
    double top;
    std::vector<CutBall> balls;
    Vec3 crest;  ///< a point of the fin's top, grid units
};

/// Fin crests where a crossing's one-sided normal reads the fin's other wall (contour::kBorrowWrongCos; found by a
/// random search).
inline std::vector<FinCrestModel> fin_crests_between_ball_cuts() {
    struct Fin {
        double top, r1, r2, h1, h2, w, x, y, tilt;
    };
    const Fin fins[] = {
        {34.971, 6.161, 3.591, 0.993, 2.145, 0.527, 20.635, 24.538, -0.715},
        {34.059, 5.870, 9.948, 0.899, 6.654, 0.589, 20.707, 24.439, -0.976},
        {34.717, 6.253, 5.264, 1.364, 2.324, 0.550, 20.637, 24.472, 0.740},
        {34.192, 6.983, 5.282, 1.278, 1.717, 0.681, 20.546, 24.458, 0.125},
        {34.889, 8.462, 4.429, 2.059, 1.539, 0.341, 20.048, 24.396, -0.580},
        {34.803, 8.536, 6.226, 2.112, 1.347, 0.502, 20.991, 24.536, 0.885},
        {34.721, 8.315, 9.197, 3.881, 1.431, 0.639, 20.502, 24.611, -0.269},
    };
    std::vector<FinCrestModel> out;
    for (const Fin& f : fins) {
        // Each ball's rim at z = top lies w / 2 from the line y = f.y.
        const double a1 = std::sqrt(f.r1 * f.r1 - f.h1 * f.h1), a2 = std::sqrt(f.r2 * f.r2 - f.h2 * f.h2);
        out.push_back({f.top,
                       {{Vec3(f.x, f.y - a1 - 0.5 * f.w, f.top + f.h1), f.r1},
                        {Vec3(f.x + f.tilt, f.y + a2 + 0.5 * f.w, f.top + f.h2), f.r2}},
                       Vec3(f.x, f.y, f.top)});
    }
    return out;
}

/// A ball added onto a box (grid units).
struct AddedBall {
    Vec3 c;
    double r;
};

/// Exact chords of ray (u, v) of set a through the box [lo, hi] plus the balls (grid units).
inline std::vector<Interval> box_plus_balls_chord(const Vec3& lo, const Vec3& hi, const std::vector<AddedBall>& balls, int a, int u,
                                                  int v) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    std::vector<std::pair<double, double>> spans;
    if (u >= lo[b] && u <= hi[b] && v >= lo[c] && v <= hi[c]) spans.push_back({lo[a], hi[a]});
    for (const AddedBall& ball : balls) {
        const double du = u - ball.c[b], dv = v - ball.c[c], d2 = du * du + dv * dv;
        if (d2 >= ball.r * ball.r) continue;
        const double half = std::sqrt(ball.r * ball.r - d2);
        spans.push_back({ball.c[a] - half, ball.c[a] + half});
    }
    std::sort(spans.begin(), spans.end());
    std::vector<std::pair<double, double>> merged;
    for (const auto& s : spans) {
        if (!merged.empty() && s.first <= merged.back().second) merged.back().second = std::max(merged.back().second, s.second);
        else merged.push_back(s);
    }
    return spans_to_intervals(merged);
}

/// Three balls added onto the top face z = top (off the nodes) of the box [6, 42]^2 x [6, top] on a 48^3 lattice.
struct BallsOnABox {
    double top;
    std::vector<AddedBall> balls;
};

/// Models where two of the balls, or one and the top face, meet in a concave crease and the third fills its
/// corner inside a cell without crossing that cell's edges (contour::kCornerFillReach; found by a random search).
inline std::vector<BallsOnABox> balls_filling_crease_corners() {
    return {
        {30.378, {{Vec3(29.9687, 27.0992, 32.5305), 6.1777}, {Vec3(23.3871, 17.6775, 31.7476), 6.1777}, {Vec3(22.9934, 22.1674, 30.4572), 5.5600}}},
        {30.311, {{Vec3(28.8136, 19.5199, 33.0826), 6.5884}, {Vec3(20.8737, 18.9724, 33.2803), 6.5884}, {Vec3(25.1646, 25.0812, 30.1605), 5.9295}}},
        {30.364, {{Vec3(17.6564, 27.7456, 32.9512), 7.0645}, {Vec3(28.0577, 30.1186, 32.7098), 7.0645}, {Vec3(22.4928, 22.9814, 30.7144), 6.3581}}},
    };
}

/// Two balls added onto the top face of the box [6, 42]^2 x [6, top] (48^3 lattice) with an air gap of 0.23 to 0.73
/// cells between them, narrowest at `mid` (found by a random search over radii, gaps and directions): where the gap
/// runs through a cell, each of its crossings reads the other wall on a neighbouring ray and gets no normal
/// (contour::kBorrowReach).
struct AirGapModel {
    BallsOnABox model;
    Vec3 mid;  ///< the gap's narrowest point, grid units
};

/// The air-gap models (see AirGapModel).
inline std::vector<AirGapModel> air_gaps_between_added_balls() {
    struct Gap {
        double r, g;
        Vec3 dir, mid;
        double top;
    };
    const Gap gaps[] = {
        {6.6890, 0.2333, Vec3(0.0487, -0.9988, 0.0080), Vec3(24.9396, 24.3920, 30.1784), 28.2129},
        {4.7165, 0.4403, Vec3(-0.9970, -0.0247, 0.0738), Vec3(24.4052, 24.2591, 30.6570), 28.6673},
        {4.9483, 0.7295, Vec3(0.9878, 0.0652, -0.1416), Vec3(24.6757, 24.9375, 30.7522), 28.4985},
        {3.6103, 0.6317, Vec3(-0.2001, 0.9775, 0.0660), Vec3(24.6508, 24.6336, 30.4429), 28.2497},
    };
    std::vector<AirGapModel> out;
    for (const Gap& k : gaps) {
        const Vec3 d = glm::normalize(k.dir);
        out.push_back({{k.top, {{k.mid - (k.r + 0.5 * k.g) * d, k.r}, {k.mid + (k.r + 0.5 * k.g) * d, k.r}}}, k.mid});
    }
    return out;
}

}  // namespace tridex::compute::testing
