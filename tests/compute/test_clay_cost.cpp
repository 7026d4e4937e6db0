// Cost per segment of the clay tools beside subtract (printed, for the notes; nothing timed is asserted): a ball of
// 3.37 cells moving 0.5 cell per segment along the top face of a box at N = 128 and 256 cells, 200 segments each,
// the CPU reference on one thread, the fastest of three runs; push also in batches of 16 through apply_clay_batch. Push and subtract press 1 cell deep; smooth rides the face.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <span>
#include <vector>

#include "compute/mesh/scan_convert.hpp"
#include "compute/model/volume.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "core/primitives.hpp"

namespace tridex::compute {
namespace {

TriDexel box_workpiece(int n) {
    Lattice L;
    L.origin_m = Vec3(0.0);
    L.cell_m = 0.3 / n;
    L.cells = {n, n, n};
    TriDexel m = TriDexel::empty(L, std::size_t{1} << 34);
    scan_convert(box_mesh(Aabb{L.to_world(Vec3(4.0)), L.to_world(Vec3(n - 4.0))}), m);
    return m;
}

/// Microseconds per segment: `segments` sweeps of the ball along +x, applied one by one (batch 1: apply_clay or
/// apply_sweep) or in batches of `batch` through apply_clay_batch (a session's sculpt step).
double run(TriDexel& m, ToolOp op, double depth_cells, int segments, int batch = 1) {
    const double n = m.lattice.cells[0], r = 3.37;
    Sweep s;
    s.op = op;
    s.tool.kind = ToolKind::kBall;
    s.tool.radius_m = r * m.lattice.cell_m;
    Vec3 p(0.5 * n - 50.0 + 0.37, 0.5 * n + 0.37, n - 4.0 + r - depth_cells);
    std::vector<Sweep> sweeps;
    for (int i = 0; i < segments; ++i) {
        const Vec3 q = p + Vec3(0.5, 0.0, 0.0);
        s.path_m = Segment{m.lattice.to_world(p), m.lattice.to_world(q)};
        sweeps.push_back(s);
        p = q;
    }
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < segments; i += batch) {
        if (batch > 1)
            apply_clay_batch(m, std::span<const Sweep>(sweeps).subspan(i, std::min(batch, segments - i)));
        else if (is_clay_op(op))
            apply_clay(m, sweeps[i]);
        else
            apply_sweep(m, sweeps[i]);
    }
    return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / segments;
}

TEST(ClayCost, PerSegmentBesideSubtract) {
    for (const int n : {128, 256}) {
        double us[3];
        double dv[3];
        const ToolOp ops[3] = {ToolOp::kSubtract, ToolOp::kPush, ToolOp::kSmooth};
        for (int k = 0; k < 3; ++k) {
            us[k] = 1e30;
            for (int rep = 0; rep < 3; ++rep) {  // the fastest of three: other work on the machine only adds
                TriDexel m = box_workpiece(n);
                const double v0 = dexel_volume_m3(m);
                us[k] = std::min(us[k], run(m, ops[k], ops[k] == ToolOp::kSmooth ? 0.2 : 1.0, 200));
                dv[k] = (dexel_volume_m3(m) - v0) / v0;
            }
        }
        double grouped = 1e30, dvg = 0.0;
        for (int rep = 0; rep < 3; ++rep) {
            TriDexel m = box_workpiece(n);
            const double v0 = dexel_volume_m3(m);
            grouped = std::min(grouped, run(m, ToolOp::kPush, 1.0, 200, 16));
            dvg = (dexel_volume_m3(m) - v0) / v0;
        }
        std::printf(
            "N = %d: subtract %.1f us/segment, push %.1f (%.1fx; in batches of 16 through apply_clay_batch %.1f, "
            "%.1fx), smooth %.1f (%.1fx); volume change subtract %.4f%%, push %.4f%% (batched %.4f%%), smooth %.4f%%\n",
            n, us[0], us[1], us[1] / us[0], grouped, grouped / us[0], us[2], us[2] / us[0], 100.0 * dv[0],
            100.0 * dv[1], 100.0 * dvg, 100.0 * dv[2]);
        EXPECT_LT(std::fabs(dv[1]), 0.02);
        EXPECT_LT(std::fabs(dvg), 0.02);
        EXPECT_LT(std::fabs(dv[2]), 0.01);
    }
}

}  // namespace
}  // namespace tridex::compute
