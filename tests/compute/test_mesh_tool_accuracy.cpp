// tests/compute/test_mesh_tool_accuracy.cpp - how close a mesh tool (ToolKind::kMesh) comes to the exact
// swept volume: an icosphere against the analytic ball tool (capsule sweep), a closed box mesh against
// the exact sweep of the box (Minkowski sum of the turned box and the segment). Each tool is added (union)
// to an empty model; per ray the mesh tool's intervals are compared with the exact ones (depth difference
// in cells, rays hit by only one of them) and every interval end is measured against the exact surface
// (|signed distance| in cells). The bound checked: sqrt(2)/(2k) (nearest tool ray) + pose spacing error +
// the tool mesh's own deviation from the exact shape + 1e-3 (float).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <cstddef>
#include <iostream>
#include <vector>

#include "compute/tools/mesh_tool.hpp"
#include "compute/tools/sweep.hpp"
#include "core/primitives.hpp"

using namespace tridex;
using namespace tridex::compute;

namespace {

constexpr int kCells = 48;

TriDexel empty_model() {
    Lattice L;
    L.origin_m = Vec3(-0.3, 0.1, 0.2);
    L.cell_m = 0.001;
    L.cells = {kCells, kCells, kCells};
    return TriDexel::empty(L, std::size_t{1} << 30);
}

struct Accuracy {
    std::size_t both = 0;      ///< rays hit by both, with the same interval count
    std::size_t only_one = 0;  ///< rays where the counts differ (hit by one only, near a silhouette)
    double max_depth = 0.0;    ///< largest end depth difference on `both` rays, cells
    double mean_depth = 0.0;
    double max_surface = 0.0;  ///< largest |signed distance| of a mesh-tool interval end from the exact surface, cells
};

/// Compares mesh-tool model `m` with exact model `e`; sdf(p) = signed distance of grid point p from the exact solid.
Accuracy measure(const TriDexel& e, const TriDexel& m, const std::function<double(const Vec3&)>& sdf) {
    Accuracy a;
    double sum = 0.0;
    std::size_t ends = 0;
    for (int s = 0; s < 3; ++s) {
        const RaySet& set = m.sets[s];
        const int ua = (s + 1) % 3, va = (s + 2) % 3;
        for (int v = 0; v < set.nv; ++v)
            for (int u = 0; u < set.nu; ++u) {
                const auto& x = e.sets[s].ray(u, v);
                const auto& y = set.ray(u, v);
                if (x.empty() && y.empty()) continue;
                if (x.size() == y.size()) {
                    ++a.both;
                    for (std::size_t k = 0; k < x.size(); ++k) {
                        const double d0 = std::fabs(double(x[k].enter) - y[k].enter), d1 = std::fabs(double(x[k].exit) - y[k].exit);
                        a.max_depth = std::max({a.max_depth, d0, d1});
                        sum += d0 + d1;
                        ends += 2;
                    }
                } else {
                    ++a.only_one;
                }
                for (const Interval& iv : y)
                    for (const float d : {iv.enter, iv.exit}) {
                        Vec3 p;
                        p[s] = d;
                        p[ua] = u;
                        p[va] = v;
                        a.max_surface = std::max(a.max_surface, std::fabs(sdf(p)));
                    }
            }
    }
    a.mean_depth = ends ? sum / static_cast<double>(ends) : 0.0;
    return a;
}

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 d = b - a;
    const double dd = glm::dot(d, d);
    const double t = dd > 0.0 ? std::clamp(glm::dot(p - a, d) / dd, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * d));
}

/// Exact signed distance (grid units) from the sweep of a box (tool frame [lo, hi], grid units) turned by
/// R, its reference point moved from a to b: outside, the distance minimised over the motion (convex in
/// s, ternary search); inside, the smallest distance to a facet plane of the Minkowski sum (box faces and
/// box edge x motion).
double box_sweep_sdf(const Vec3& p, const glm::dmat3& R, const Vec3& lo, const Vec3& hi, const Vec3& a, const Vec3& b) {
    const glm::dmat3 Rt = glm::transpose(R);
    const Vec3 c = 0.5 * (lo + hi), e = 0.5 * (hi - lo), d = b - a;
    auto outside = [&](double s) {
        const Vec3 q = glm::abs(Rt * (p - a - s * d) - c) - e;
        return glm::length(glm::max(q, Vec3(0.0)));
    };
    double l = 0.0, r = 1.0;
    for (int i = 0; i < 200; ++i) {
        const double m1 = l + (r - l) / 3.0, m2 = r - (r - l) / 3.0;
        if (outside(m1) < outside(m2)) r = m2;
        else l = m1;
    }
    const double out = std::min({outside(0.5 * (l + r)), outside(0.0), outside(1.0)});
    if (out > 1e-9) return out;
    std::vector<Vec3> normals;
    for (int i = 0; i < 3; ++i) {
        normals.push_back(R[i]);
        normals.push_back(-R[i]);
        const Vec3 x = glm::cross(R[i], d);
        if (glm::length(x) > 1e-12) {
            normals.push_back(glm::normalize(x));
            normals.push_back(-glm::normalize(x));
        }
    }
    double inside = INFINITY;
    for (const Vec3& n : normals) {
        double support = glm::dot(n, R * c);
        for (int i = 0; i < 3; ++i) support += e[i] * std::fabs(glm::dot(n, R[i]));
        support += std::max(0.0, glm::dot(n, d));
        inside = std::min(inside, support - glm::dot(n, p - a));
    }
    return -inside;
}

/// Exact chord [t0, t1] of the ray o + t e_axis with the sweep of the box (as box_sweep_sdf): the points
/// (t, s) with every box slab constraint on o + t e_axis - a - s (b - a) and 0 <= s <= 1 form a convex
/// polygon; t0, t1 are the extreme t over its vertices (all pairs of constraint lines). False when empty.
bool exact_box_chord(const Vec3& o, int axis, const glm::dmat3& R, const Vec3& lo, const Vec3& hi, const Vec3& a, const Vec3& b,
                     double& t0, double& t1) {
    const Vec3 d = b - a;
    struct Line {
        double alpha, beta, gamma;  // alpha t + beta s + gamma <= 0
    };
    std::vector<Line> lines{{0.0, -1.0, 0.0}, {0.0, 1.0, -1.0}};
    for (int j = 0; j < 3; ++j) {
        const Vec3 n = R[j];
        const double alpha = n[axis], beta = -glm::dot(n, d), g = glm::dot(n, o - a);
        lines.push_back({alpha, beta, g - hi[j]});     // n.(p - a - s d) <= hi_j
        lines.push_back({-alpha, -beta, lo[j] - g});   // n.(p - a - s d) >= lo_j
    }
    t0 = INFINITY;
    t1 = -INFINITY;
    for (std::size_t i = 0; i < lines.size(); ++i)
        for (std::size_t j = i + 1; j < lines.size(); ++j) {
            const Line &p = lines[i], &q = lines[j];
            const double det = p.alpha * q.beta - p.beta * q.alpha;
            if (std::fabs(det) < 1e-12) continue;
            const double t = (-p.gamma * q.beta + p.beta * q.gamma) / det;
            const double s = (-p.alpha * q.gamma + p.gamma * q.alpha) / det;
            bool feasible = true;
            for (const Line& l : lines) feasible = feasible && l.alpha * t + l.beta * s + l.gamma <= 1e-9;
            if (!feasible) continue;
            t0 = std::min(t0, t);
            t1 = std::max(t1, t);
        }
    return t0 <= t1;
}

void print(const char* what, int k, const Accuracy& a, double bound) {
    std::cout << what << " k=" << k << ": rays compared " << a.both << ", rays hit by one only " << a.only_one
              << ", per-ray depth difference max " << a.max_depth << " mean " << a.mean_depth
              << " cells; surface distance max " << a.max_surface << " cells (bound " << bound << ")\n";
}

}  // namespace

TEST(MeshToolAccuracy, IcosphereToolAgainstTheAnalyticBall) {
    const double r_cells = 6.3;
    for (int k : {2, 4, 8}) {
        for (int moving = 0; moving < 2; ++moving) {
            TriDexel exact = empty_model(), mesh = empty_model();
            const Lattice& L = exact.lattice;
            const TriMesh sphere = icosphere_mesh(Vec3(0.0), r_cells * L.cell_m, 5);
            double sagitta = 0.0;  // how far the inscribed polyhedron lies inside the sphere, cells
            for (const auto& t : sphere.triangles) {
                const Vec3 &p0 = sphere.positions[t[0]], &p1 = sphere.positions[t[1]], &p2 = sphere.positions[t[2]];
                const Vec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
                sagitta = std::max(sagitta, r_cells - glm::dot(n, p0) / L.cell_m);
            }
            const Vec3 ga(20.3, 21.7, 19.1), gb = moving ? Vec3(29.6, 25.2, 27.9) : ga;
            Sweep s;
            s.op = ToolOp::kUnion;
            s.path_m = Segment{L.to_world(ga), L.to_world(gb)};
            s.axis = Vec3(0.2, 0.5, 0.8);
            s.tool = SweepTool{ToolKind::kBall, r_cells * L.cell_m, 0.0};
            apply_sweep(exact, s);
            s.tool = SweepTool{ToolKind::kMesh, 0.0, 0.0, MeshTool::create(sphere, k)};
            apply_sweep(mesh, s);
            const Accuracy a = measure(exact, mesh, [&](const Vec3& p) { return segment_distance(p, ga, gb) - r_cells; });
            const double scallop = moving ? r_cells - std::sqrt(r_cells * r_cells - 0.0625) : 0.0;
            const double bound = std::sqrt(2.0) / (2.0 * k) + scallop + sagitta + 1e-3;
            print(moving ? "icosphere r=6.3 moving" : "icosphere r=6.3 still ", k, a, bound);
            EXPECT_GT(a.both, 300u);
            EXPECT_LE(a.max_surface, bound);
            EXPECT_LT(a.only_one, a.both / 5);
        }
    }
}

TEST(MeshToolAccuracy, BoxMeshToolAgainstTheExactBoxSweep) {
    const Vec3 lo(-4.6, -6.2, -3.4), hi(5.8, 3.2, 10.4);  // cells, tool frame
    struct Case {
        const char* name;
        Vec3 axis, ga, gb;
    };
    const Case cases[] = {
        {"box axis-aligned still ", Vec3(0, 0, 1), Vec3(20.0, 21.0, 19.0), Vec3(20.0, 21.0, 19.0)},
        {"box turned still      ", Vec3(0.3, -0.4, 0.85), Vec3(20.2, 21.6, 19.3), Vec3(20.2, 21.6, 19.3)},
        {"box turned moving     ", Vec3(0.3, -0.4, 0.85), Vec3(18.2, 20.6, 17.3), Vec3(27.9, 26.1, 24.4)},
    };
    for (const Case& c : cases) {
        for (int k : {2, 4, 8}) {
            TriDexel mesh = empty_model();
            const Lattice& L = mesh.lattice;
            Sweep s;
            s.op = ToolOp::kUnion;
            s.path_m = Segment{L.to_world(c.ga), L.to_world(c.gb)};
            s.axis = c.axis;
            s.tool = SweepTool{ToolKind::kMesh, 0.0, 0.0, MeshTool::create(box_mesh(Aabb{lo * L.cell_m, hi * L.cell_m}), k)};
            apply_sweep(mesh, s);
            // The exact model: per ray, the chord of the swept box (exact_box_chord).
            const glm::dmat3 R = tool_rotation(c.axis);
            auto sdf = [&](const Vec3& p) { return box_sweep_sdf(p, R, lo, hi, c.ga, c.gb); };
            TriDexel exact = empty_model();
            for (int a = 0; a < 3; ++a) {
                const int ua = (a + 1) % 3, va = (a + 2) % 3;
                for (int v = 0; v < exact.sets[a].nv; ++v)
                    for (int u = 0; u < exact.sets[a].nu; ++u) {
                        Vec3 o(0.0);
                        o[ua] = u;
                        o[va] = v;
                        double t0, t1;
                        if (exact_box_chord(o, a, R, lo, hi, c.ga, c.gb, t0, t1) && t0 < t1)
                            exact.sets[a].ray(u, v).push_back(Interval{static_cast<float>(t0), static_cast<float>(t1), 0, 0});
                    }
            }
            const Accuracy acc = measure(exact, mesh, sdf);
            const bool moving = c.ga != c.gb;
            const double bound = std::sqrt(2.0) / (2.0 * k) + (moving ? 0.25 : 0.0) + 1e-3;  // poses <= 0.5 cell apart
            print(c.name, k, acc, bound);
            EXPECT_GT(acc.both, 300u);
            EXPECT_LE(acc.max_surface, bound);
            if (c.axis == Vec3(0, 0, 1) && !moving) {
                // Faces off the lattice, no rotation: every ray's depths are exact up to float rounding.
                EXPECT_EQ(acc.only_one, 0u);
                EXPECT_LT(acc.max_depth, 1e-4);
            }
        }
    }
}
