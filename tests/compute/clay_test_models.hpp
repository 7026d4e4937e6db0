// tests/compute/clay_test_models.hpp - analytic solids for the clay tests: every ray of the three sets sampled from
// one implicit function (so the sets agree), a plane slab, a sphere and a noisy sphere, and roughness figures.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <vector>

#include "compute/model/tridexel.hpp"
#include "compute/tools/clay_field.hpp"
#include "compute/tools/sweep.hpp"

namespace tridex::compute::clay_test {

/// Implicit solid in grid units: < 0 inside.
using Implicit = std::function<double(double x, double y, double z)>;

/// A cubic lattice of `cells` cells of 1 mm from the origin.
inline Lattice cube_lattice(int cells) {
    Lattice L;
    L.origin_m = Vec3(0.0);
    L.cell_m = 1e-3;
    L.cells = {cells, cells, cells};
    return L;
}

/// Samples every ray of the three sets from `f` (sign changes at 1/8 cell, refined by bisection).
inline TriDexel from_implicit(const Lattice& L, const Implicit& f) {
    TriDexel m = TriDexel::empty(L, std::size_t(1) << 30);
    for (int a = 0; a < 3; ++a) {
        RaySet& set = m.sets[a];
        for (int v = 0; v < set.nv; ++v)
            for (int u = 0; u < set.nu; ++u) {
                double p[3];
                p[(a + 1) % 3] = u;
                p[(a + 2) % 3] = v;
                auto at = [&](double t) {
                    p[a] = t;
                    return f(p[0], p[1], p[2]);
                };
                std::vector<Interval>& ray = set.ray(u, v);
                const double end = L.cells[a];
                double t0 = 0.0, f0 = at(0.0), enter = 0.0;
                bool in = f0 < 0.0;
                for (double t1 = 0.125; t1 <= end + 1e-9; t1 += 0.125) {
                    const double f1 = at(t1);
                    if ((f1 < 0.0) != in) {
                        double lo = t0, hi = t1;
                        for (int k = 0; k < 50; ++k) {
                            const double mid = 0.5 * (lo + hi);
                            if ((at(mid) < 0.0) == in)
                                lo = mid;
                            else
                                hi = mid;
                        }
                        const double root = 0.5 * (lo + hi);
                        if (!in)
                            enter = root;
                        else if (static_cast<float>(root) > static_cast<float>(enter))
                            ray.push_back({static_cast<float>(enter), static_cast<float>(root), 0, 0});
                        in = !in;
                    }
                    t0 = t1;
                    f0 = f1;
                }
            }
    }
    return m;
}

/// A slab: material in [4.4, 43.6] x [4.4, 43.6] x [4.4, z0] (grid units; for cube_lattice(48)).
inline Implicit slab(double z0) {
    return [z0](double x, double y, double z) { return std::max({4.4 - x, x - 43.6, 4.4 - y, y - 43.6, 4.4 - z, z - z0}); };
}

/// A ball of radius rho (grid units) centred at (cx, cy, cz) (grid units) on cube_lattice(cells).
inline TriDexel sphere_model(int cells, double cx, double cy, double cz, double rho) {
    return from_implicit(cube_lattice(cells), [=](double x, double y, double z) {
        return std::sqrt((x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz)) - rho;
    });
}

/// True when a and b are the same float bit for bit (NaNs with the same payload included).
inline bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof(float)) == 0; }

/// True when the two models (one lattice) hold the same interval ends on every ray, bit for bit.
inline bool same_rays(const TriDexel& a, const TriDexel& b) {
    for (int s = 0; s < 3; ++s)
        for (std::size_t r = 0; r < a.sets[s].rays.size(); ++r) {
            const auto &x = a.sets[s].rays[r], &y = b.sets[s].rays[r];
            if (x.size() != y.size()) return false;
            for (std::size_t i = 0; i < x.size(); ++i)
                if (x[i].enter != y[i].enter || x[i].exit != y[i].exit) return false;
        }
    return true;
}

/// Sum of the three sets' interval lengths / 3, cells^3.
inline double volume_cells(const TriDexel& m) {
    double v = 0.0;
    for (const RaySet& s : m.sets)
        for (const auto& r : s.rays)
            for (const Interval& iv : r) v += static_cast<double>(iv.exit) - static_cast<double>(iv.enter);
    return v / 3.0;
}

/// Roughness of a model that should be a sphere about `c` (grid units): the RMS over every crossing of the three
/// sets within `shell` cells of radius `rho` and above the cap's height `cap` * rho (z - c_z >= cap * rho) of
/// (|p - c| - mean |p - c|), cells.
inline double radial_rms(const TriDexel& m, const double c[3], double rho, double shell, double cap) {
    std::vector<double> rs;
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = m.sets[a];
        for (int v = 0; v < set.nv; ++v)
            for (int u = 0; u < set.nu; ++u)
                for (const Interval& iv : set.ray(u, v))
                    for (float t : {iv.enter, iv.exit}) {
                        double p[3];
                        p[(a + 1) % 3] = u;
                        p[(a + 2) % 3] = v;
                        p[a] = t;
                        const double r = std::sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                                                   (p[2] - c[2]) * (p[2] - c[2]));
                        if (std::fabs(r - rho) < shell && p[2] - c[2] >= cap * rho) rs.push_back(r);
                    }
    }
    double mean = 0.0;
    for (double r : rs) mean += r;
    mean /= static_cast<double>(rs.size());
    double ss = 0.0;
    for (double r : rs) ss += (r - mean) * (r - mean);
    return std::sqrt(ss / static_cast<double>(rs.size()));
}

/// Normal variation of a model that should be a sphere about `c`: the mean angle (degrees) between the node field's
/// normal (central differences of clay_node_phi) and the radial direction, over nodes with |phi| < 1 cell whose
/// height above the centre is at least `cap` * their distance from it (the cap the tests brush).
inline double normal_deviation_deg(const TriDexel& m, const double c[3], double cap) {
    double sum = 0.0;
    std::size_t n = 0;
    const Lattice& L = m.lattice;
    for (int k = 1; k < L.cells[2]; ++k)
        for (int j = 1; j < L.cells[1]; ++j)
            for (int i = 1; i < L.cells[0]; ++i) {
                const float phi = clay_node_phi(m, i, j, k);
                if (!(std::fabs(phi) < 1.0f)) continue;
                const double g[3] = {clay_node_phi(m, i + 1, j, k) - clay_node_phi(m, i - 1, j, k),
                                     clay_node_phi(m, i, j + 1, k) - clay_node_phi(m, i, j - 1, k),
                                     clay_node_phi(m, i, j, k + 1) - clay_node_phi(m, i, j, k - 1)};
                const double r[3] = {i - c[0], j - c[1], k - c[2]};
                const double gl = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
                const double rl = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
                if (!(gl > 0.0) || !(rl > 0.0) || r[2] < cap * rl) continue;
                const double cosang = std::clamp((g[0] * r[0] + g[1] * r[1] + g[2] * r[2]) / (gl * rl), -1.0, 1.0);
                sum += std::acos(cosang) * 180.0 / M_PI;
                ++n;
            }
    return n ? sum / static_cast<double>(n) : 0.0;
}

/// A clay sweep (op push, smooth or pull) of a ball of radius_cells on cube_lattice, from a to b (grid units = mm).
inline Sweep clay_sweep(ToolOp op, const Vec3& a_cells, const Vec3& b_cells, double radius_cells) {
    constexpr double kCell = 1e-3;  // cube_lattice: 1 mm cells from the origin
    Sweep s;
    s.op = op;
    s.tool.kind = ToolKind::kBall;
    s.tool.radius_m = radius_cells * kCell;
    s.path_m = Segment{a_cells * kCell, b_cells * kCell};
    return s;
}

}  // namespace tridex::compute::clay_test
