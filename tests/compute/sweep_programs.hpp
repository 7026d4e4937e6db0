// tests/compute/sweep_programs.hpp - test models and random sweep programs shared by the Boolean and undo tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "compute/mesh/scan_convert.hpp"
#include "compute/tools/sweep.hpp"
#include "core/primitives.hpp"

namespace tridex::compute::test {


inline TriDexel box_model(int cells, double lo, double hi) {
    Lattice L;
    L.origin_m = Vec3(-0.4, 0.25, 0.9);
    L.cell_m = 0.001;
    L.cells = {cells, cells, cells};
    TriDexel m = TriDexel::empty(L, std::size_t{1} << 30);
    if (hi > lo) scan_convert(box_mesh(Aabb{L.to_world(Vec3(lo)), L.to_world(Vec3(hi))}), m);
    return m;
}

/// Number of rays that differ (bitwise, materials included) and the largest depth difference, cells.
struct Diff {
    std::size_t rays = 0;
    double max_cells = 0.0;
};

inline Diff compare(const TriDexel& a, const TriDexel& b) {
    Diff d;
    for (int s = 0; s < 3; ++s)
        for (std::size_t i = 0; i < a.sets[s].rays.size(); ++i) {
            const auto& x = a.sets[s].rays[i];
            const auto& y = b.sets[s].rays[i];
            bool same = x.size() == y.size();
            for (std::size_t k = 0; same && k < x.size(); ++k) {
                same = std::memcmp(&x[k].enter, &y[k].enter, 4) == 0 && std::memcmp(&x[k].exit, &y[k].exit, 4) == 0 &&
                       x[k].enter_material == y[k].enter_material && x[k].exit_material == y[k].exit_material;
                d.max_cells = std::max({d.max_cells, std::fabs(double(x[k].enter) - y[k].enter), std::fabs(double(x[k].exit) - y[k].exit)});
            }
            if (!same) ++d.rays;
        }
    return d;
}

/// A random stroke program: strokes of a few segments each, every tool and operation, some positions
/// snapped to lattice nodes and planes and radii to whole cells (rays grazing and tangent to the tool).
inline std::vector<Sweep> random_program(const Lattice& L, int segments, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(6.0, L.cells[0] - 6.0), unit(0.0, 1.0);
    std::vector<Sweep> out;
    Vec3 p = L.to_world(Vec3(pos(rng), pos(rng), pos(rng)));
    Sweep s;
    while (static_cast<int>(out.size()) < segments) {
        if (out.empty() || unit(rng) < 0.1) {  // a new stroke: tool, operation, material
            const double pick = unit(rng);
            s.op = pick < 0.5 ? ToolOp::kSubtract : pick < 0.8 ? ToolOp::kUnion : ToolOp::kPaint;
            s.material = static_cast<std::uint8_t>(1 + rng() % 6);
            const bool flat = unit(rng) < 0.35;
            double r = 0.4 + 5.0 * unit(rng);
            if (unit(rng) < 0.3) r = std::max(1.0, std::round(r));  // whole cells
            s.tool = SweepTool{flat ? ToolKind::kFlatEnd : ToolKind::kBall, r * L.cell_m, (2.0 + 6.0 * unit(rng)) * L.cell_m};
            Vec3 axis(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
            if (unit(rng) < 0.4) axis = Vec3(0.0, 0.0, 1.0);  // aligned with the lattice
            s.axis = glm::length(axis) > 1e-3 ? axis : Vec3(1.0, 0.0, 0.0);
            p = L.to_world(Vec3(pos(rng), pos(rng), pos(rng)));
        }
        Vec3 g = L.to_grid(p) + Vec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5) * 3.0;
        if (unit(rng) < 0.25) g = glm::round(g);                 // on a lattice node
        else if (unit(rng) < 0.25) g.x = std::round(g.x);        // on a lattice plane
        g = glm::clamp(g, Vec3(2.0), Vec3(L.cells[0] - 2.0));
        const Vec3 q = L.to_world(g);
        s.path_m = Segment{p, unit(rng) < 0.05 ? p : q};  // some zero-length segments
        out.push_back(s);
        p = q;
    }
    return out;
}


}  // namespace tridex::compute::test
