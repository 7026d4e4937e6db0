// tests/compute/site_grooves.hpp - the sculpt-site tests' workpiece and strokes: the journal tests' box, and grooves
// along x on its top face by one site each.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/tool_sample.hpp"
#include "journal_stream.hpp"

namespace tridex::app {

inline compute::TriDexel box_model() { return tridex::test::journal_box_model(); }

// A groove of `n` samples along x on the top face at height y_m, by `site`, starting at device time t0_s; the last
// sample lifts the tool (op none), which ends the stroke.
inline std::vector<ToolSample> groove(std::uint8_t site, double y_m, double x0_m, double x1_m, int n, double t0_s) {
    std::vector<ToolSample> s(static_cast<std::size_t>(n) + 1);
    for (int i = 0; i <= n; ++i) {
        ToolSample& x = s[static_cast<std::size_t>(i)];
        x.site = site;
        x.t_s = t0_s + i * 1e-3;
        x.position = Vec3(x0_m + (x1_m - x0_m) * std::min(i, n - 1) / (n - 1), y_m, 0.046);
        x.tool.radius_m = 0.005;
        x.op = i < n ? ToolOp::kSubtract : ToolOp::kNone;
    }
    return s;
}

inline std::vector<ToolSample> slice(const std::vector<ToolSample>& s, std::size_t a, std::size_t b) {
    return {s.begin() + static_cast<std::ptrdiff_t>(a), s.begin() + static_cast<std::ptrdiff_t>(b)};
}

}  // namespace tridex::app
