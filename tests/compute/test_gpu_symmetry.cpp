// Symmetry on the GPU sculpt path: batches of strokes with their mirrored and radial copies (ball, flat-end and mesh
// tools, the mirrored mesh tool cut with its reflection) give the CPU reference's rays bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/tools/sample_sweep.hpp"
#include "compute/tools/symmetry.hpp"
#include "core/primitives.hpp"
#include "gpu/context.hpp"

namespace tridex::compute {
namespace {

TriDexel box_model() {
    TriDexel m = TriDexel::empty(Lattice::around(Aabb{Vec3(-0.05), Vec3(0.05)}, 48), std::size_t(1) << 30);
    scan_convert(box_mesh(Aabb{Vec3(-0.0487), Vec3(0.0487)}), m);
    return m;
}

TEST(GpuSymmetry, StrokesWithTheirCopiesMatchTheCpuBitForBit) {
    gpu::Context ctx = gpu::Context::create({});
    {
        TriDexel cpu = box_model(), gpu_model = box_model();
        GpuSculptor sculptor(ctx, gpu_model);
        TriMesh wedge;
        wedge.positions = {Vec3(0.0), Vec3(0.012, 0.0, -0.004), Vec3(0.012, 0.0, 0.004), Vec3(0.004, 0.012, 0.0)};
        wedge.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
        const auto mesh = MeshTool::create(wedge, 4, "wedge");
        const auto mirror = mirrored_mesh_tool(*mesh);
        const char* forms[] = {"x", "radial:5:z", "xyz", "yz"};
        const ToolShape tools[] = {ToolShape{ToolKind::kBall, 0.005, 0.0, 0}, ToolShape{ToolKind::kFlatEnd, 0.004, 0.02, 0},
                                   ToolShape{ToolKind::kMesh, mesh->bounding_radius_m(), 0.0, 0},
                                   ToolShape{ToolKind::kMesh, mesh->bounding_radius_m(), 0.0, 0}};
        const ToolOp ops[] = {ToolOp::kSubtract, ToolOp::kUnion, ToolOp::kSubtract, ToolOp::kPaint};
        std::size_t sweeps = 0;
        for (int k = 0; k < 4; ++k) {
            std::vector<ToolSample> s(25);
            for (int i = 0; i < 25; ++i) {
                const double u = i / 24.0;
                s[i].position = Vec3(0.01 + 0.02 * u, -0.015 + 0.02 * u + 0.004 * k, 0.047 - 0.003 * std::sin(5.0 * u));
                s[i].orientation = glm::normalize(Quat(0.3, 0.9 - 0.2 * u, 0.1 * k, 0.05));
                s[i].tool = tools[k];
                s[i].op = ops[k];
                s[i].material = 4;
                s[i].symmetry = parse_symmetry(forms[k], "test");
            }
            std::vector<Sweep> batch;
            for (int i = 1; i < 25; ++i)
                sample_sweeps(s[i - 1], s[i], tools[k].kind == ToolKind::kMesh ? mesh : nullptr, mirror,
                              symmetry_centre(cpu.lattice), batch);
            for (const Sweep& sw : batch) apply_sweep(cpu, sw);
            sculptor.apply(batch);
            sweeps += batch.size();
            EXPECT_EQ(model_digest(cpu), model_digest(gpu_model)) << forms[k] << " with a " << to_string(tools[k].kind) << " tool";
        }
        EXPECT_EQ(sweeps, 24u * (2 + 5 + 8 + 4));
        EXPECT_NE(model_digest(cpu), model_digest(box_model()));
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::compute
