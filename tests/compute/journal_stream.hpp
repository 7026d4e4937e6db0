// tests/compute/journal_stream.hpp - the sculpt-thread tests' workpieces and tool streams.
#pragma once

#include <cmath>
#include <vector>

#include "compute/mesh/scan_convert.hpp"
#include "compute/model/tridexel.hpp"
#include "core/primitives.hpp"
#include "core/tool_sample.hpp"

namespace tridex::test {

/// A 0.1 m box about the origin, scan-converted at `cells` cells along each side.
inline compute::TriDexel box_model(int cells) {
    const Aabb box{Vec3(-0.05), Vec3(0.05)};
    compute::TriDexel m = compute::TriDexel::empty(compute::Lattice::around(box, cells), std::size_t(1) << 30);
    compute::scan_convert(box_mesh(box), m);
    return m;
}

/// A 0.1 m box at 40 cells.
inline compute::TriDexel journal_box_model() { return box_model(40); }

/// `count` (>= 2) samples, 1 ms apart, of one subtracting stroke along a wavy path across the box's +z face (7 mm
/// ball; made_s 100 + i s).
inline std::vector<ToolSample> wavy_cut(int count) {
    std::vector<ToolSample> s(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
        const double u = i / static_cast<double>(count - 1);
        s[i].t_s = i * 1e-3;
        s[i].position = Vec3(-0.06 + 0.12 * u, 0.02 * std::sin(9.0 * u), 0.048 - 0.004 * std::sin(5.0 * u));
        s[i].tool.radius_m = 0.007;
        s[i].op = ToolOp::kSubtract;
        s[i].made_s = 100.0 + i;
    }
    return s;
}

/// 450 samples, 1 ms apart, of a wavy path across the box's +z face: a subtract, then a union, then a paint stroke
/// (150 samples each, 6 mm ball, material 3).
inline std::vector<ToolSample> journal_stream() {
    std::vector<ToolSample> s(450);
    for (int i = 0; i < 450; ++i) {
        const double u = (i % 150) / 149.0;
        s[i].t_s = i * 1e-3;
        s[i].position = Vec3(-0.06 + 0.12 * u, 0.02 * std::sin(9.0 * u) + 0.01 * (i / 150), 0.048 - 0.004 * std::sin(5.0 * u));
        s[i].tool.radius_m = 0.006;
        s[i].op = i < 150 ? ToolOp::kSubtract : i < 300 ? ToolOp::kUnion : ToolOp::kPaint;
        s[i].material = 3;
    }
    return s;
}

}  // namespace tridex::test
