// tests/compute/island_models.hpp - a block with a knob on top and one stroke that cuts the knob's neck, leaving its
// top floating as a speck (smaller than the tool's ball): shared by the speck tests of the history, the sculpt thread
// and the journal.
#pragma once

#include <vector>

#include "compute/model/interval_ops.hpp"
#include "core/tool_sample.hpp"
#include "sweep_programs.hpp"

namespace tridex::compute::test {

inline constexpr int kKnobCells = 48;        ///< lattice cells per side (1 mm cells)
inline constexpr double kKnobToolCells = 3;  ///< the cutting ball's radius, cells: its ball is 113 cells^3

/// The block [6.5, 30.5]^3 (grid units), with `knob` the box [18.5, 24.5]^2 x [29.5, 36.5] on its top face united in.
inline TriDexel knob_model(bool knob = true) {
    TriDexel m = box_model(kKnobCells, 6.5, 30.5);
    if (!knob) return m;
    TriDexel part = TriDexel::empty(m.lattice, std::size_t{1} << 30);
    scan_convert(box_mesh(Aabb{m.lattice.to_world(Vec3(18.5, 18.5, 29.5)), m.lattice.to_world(Vec3(24.5, 24.5, 36.5))}), part);
    for (int a = 0; a < 3; ++a)
        for (std::size_t r = 0; r < part.sets[a].rays.size(); ++r)
            for (const Interval& iv : part.sets[a].rays[r]) union_interval_changed(m.sets[a].rays[r], iv.enter, iv.exit, 0);
    return m;
}

/// The stroke's path (world m): a zigzag of passes along x at z = 31.5, y = 17.5, 19.5, ... 25.5, from x = 14 to 29,
/// which cuts z in [28.7, 34.3] under the knob and leaves its top, [34.3, 36.5], about 80 cells^3, floating.
inline std::vector<Vec3> knob_cut_path(const Lattice& l) {
    std::vector<Vec3> p;
    for (int k = 0; k < 5; ++k) {
        const double y = 17.5 + 2.0 * k;
        const bool fwd = k % 2 == 0;
        p.push_back(l.to_world(Vec3(fwd ? 14.0 : 29.0, y, 31.5)));
        p.push_back(l.to_world(Vec3(fwd ? 29.0 : 14.0, y, 31.5)));
    }
    return p;
}

/// The stroke as subtract sweeps of a ball of kKnobToolCells cells.
inline std::vector<Sweep> knob_cut(const Lattice& l) {
    const std::vector<Vec3> p = knob_cut_path(l);
    std::vector<Sweep> out;
    for (std::size_t i = 1; i < p.size(); ++i) {
        Sweep s;
        s.op = ToolOp::kSubtract;
        s.tool = SweepTool{ToolKind::kBall, kKnobToolCells * l.cell_m, 0.0};
        s.path_m = Segment{p[i - 1], p[i]};
        out.push_back(s);
    }
    return out;
}

/// The stroke as tool samples at 1 kHz from t0_s, `per_leg` samples per leg of the path (the ball, subtract).
inline std::vector<ToolSample> knob_cut_samples(const Lattice& l, double t0_s, int per_leg = 40) {
    const std::vector<Vec3> p = knob_cut_path(l);
    std::vector<ToolSample> out;
    for (std::size_t i = 1; i < p.size(); ++i)
        for (int k = i == 1 ? 0 : 1; k <= per_leg; ++k) {
            ToolSample s;
            s.t_s = t0_s + static_cast<double>(out.size()) * 1e-3;
            s.position = p[i - 1] + (p[i] - p[i - 1]) * (k / static_cast<double>(per_leg));
            s.tool.radius_m = kKnobToolCells * l.cell_m;
            s.op = ToolOp::kSubtract;
            out.push_back(s);
        }
    return out;
}

}  // namespace tridex::compute::test
