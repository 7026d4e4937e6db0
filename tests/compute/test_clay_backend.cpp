// Clay sweeps through the sculpting backends: the GPU path (Booleans and clay in Vulkan compute: GpuSculptor and
// GpuClay) gives the CPU path's model bit for bit, slabs included, with symmetric copies too; undo restores exactly.
#include <gtest/gtest.h>

#include <cstdio>

#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/runtime/sculpt_history.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "compute/tools/sample_sweep.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"
#include "gpu/context.hpp"

namespace tridex::app {
namespace {

compute::TriDexel box_model() {
    const Aabb box{Vec3(-0.05), Vec3(0.05)};
    compute::TriDexel m = compute::TriDexel::empty(compute::Lattice::around(box, 48), std::size_t(1) << 30);
    compute::scan_convert(box_mesh(box), m);
    return m;
}

compute::Sweep sweep(ToolOp op, const Vec3& a, const Vec3& b) {
    compute::Sweep s;
    s.op = op;
    s.tool.kind = ToolKind::kBall;
    s.tool.radius_m = 0.006;
    s.path_m = Segment{a, b};
    return s;
}

// Subtract, push and smooth interleaved over the +z face, in batches of 16.
std::vector<std::vector<compute::Sweep>> batches() {
    std::vector<std::vector<compute::Sweep>> out(6);
    Vec3 p(-0.02, 0.0, 0.05 + 0.006 - 0.001);
    for (int k = 0; k < 96; ++k) {
        const ToolOp op = k < 32 ? ToolOp::kSubtract : k < 64 ? ToolOp::kPush : ToolOp::kSmooth;
        const Vec3 q = p + Vec3(0.0012, 0.0003 * ((k % 5) - 2), k < 64 ? -0.00005 : 0.0);
        out[k / 16].push_back(sweep(op, p, q));
        p = q;
        if (k == 31 || k == 63) p = Vec3(-0.02, 0.004 * (k / 32), p.z);
    }
    return out;
}

void expect_same(const compute::TriDexel& a, const compute::TriDexel& b) {
    for (int s = 0; s < 3; ++s)
        for (std::size_t r = 0; r < a.sets[s].rays.size(); ++r) {
            const auto& x = a.sets[s].rays[r];
            const auto& y = b.sets[s].rays[r];
            ASSERT_EQ(x.size(), y.size()) << "set " << s << " ray " << r;
            for (std::size_t k = 0; k < x.size(); ++k) {
                ASSERT_EQ(x[k].enter, y[k].enter);
                ASSERT_EQ(x[k].exit, y[k].exit);
                ASSERT_EQ(x[k].enter_material, y[k].enter_material);
                ASSERT_EQ(x[k].exit_material, y[k].exit_material);
            }
        }
}

// The GPU path with its clay on the GPU clay kernel (`gpu_clay`: forced even on a CPU Vulkan implementation) or where
// make_boolean_backend places it (the CPU reference on the mirror on lavapipe) gives the CPU path's model, and undo
// restores the start on both.
void check_gpu_path(bool gpu_clay) {
    compute::TriDexel cpu_model = box_model();
    const compute::TriDexel start = cpu_model;
    compute::TriDexel gpu_model = cpu_model;
    auto cpu = make_cpu_backend(cpu_model);
    BackendChoice gpu;
    try {  // the GPU path forced: on lavapipe the device's type alone would choose the CPU pool
        gpu = make_boolean_backend(gpu_model, {BackendMode::kGpu, false, gpu_clay}, false);
    } catch (const tridex::Error& e) {
        GTEST_SKIP() << "no Vulkan device: " << e.what();
    }
    const bool cpu_device = gpu.backend->gpu_context()->properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    const bool on_kernel = gpu_clay || !cpu_device;
    EXPECT_EQ(gpu.backend->clay_path(), on_kernel ? "gpu" : "cpu");
    EXPECT_EQ(gpu.backend->clay_reason().empty(), on_kernel) << gpu.backend->clay_reason();
    EXPECT_EQ(cpu->clay_path(), "cpu");
    SculptHistory hc(cpu_model, *cpu), hg(gpu_model, *gpu.backend);
    std::size_t changed = 0;
    for (const auto& b : batches()) {
        const compute::BooleanStats sc = hc.apply(b);
        const compute::BooleanStats sg = hg.apply(b);
        EXPECT_EQ(sc.rays_changed > 0,
                  sg.rays_changed > 0);  // the paths count a ray changed by several sweeps differently
        changed += sc.rays_changed;
    }
    EXPECT_GT(changed, 0u);
    expect_same(cpu_model, gpu_model);
    // Placed on the kernel, the GPU path's clay ran in Vulkan, not on the CPU reference.
    EXPECT_EQ(cpu->gpu_clay_stats(), nullptr);
    const compute::GpuClayStats* clay = gpu.backend->gpu_clay_stats();
    if (on_kernel) {
        ASSERT_NE(clay, nullptr);
        EXPECT_GE(clay->fields, 3u);  // the push groups and at least one smooth group (smooth sweeps go in groups too)
        EXPECT_GT(clay->rays_resampled, 100u);
        EXPECT_EQ(clay->host_fields, 0u);
    } else {
        EXPECT_EQ(clay, nullptr);
    }
    // The slabs hold what the mirror holds.
    const compute::GpuDexelSlabs* slabs = gpu.backend->gpu_slabs();
    ASSERT_NE(slabs, nullptr);
    std::vector<compute::Interval> ray;
    for (int a = 0; a < 3; ++a) {
        const compute::RaySet& set = gpu_model.sets[a];
        for (int v = 0; v < set.nv; ++v)
            for (int u = 0; u < set.nu; ++u) {
                slabs->read_ray(a, u, v, ray);
                const auto& want = set.ray(u, v);
                ASSERT_EQ(ray.size(), want.size()) << a << " " << u << " " << v;
                for (std::size_t k = 0; k < ray.size(); ++k) {
                    ASSERT_EQ(ray[k].enter, want[k].enter);
                    ASSERT_EQ(ray[k].exit, want[k].exit);
                }
            }
    }
    // Undo all strokes on both: back to the start exactly.
    hc.end_stroke();
    hg.end_stroke();
    while (hc.undo().serial != 0) {}
    while (hg.undo().serial != 0) {}
    expect_same(cpu_model, start);
    expect_same(gpu_model, start);
}

TEST(ClayBackend, GpuPathWithTheClayKernelEqualsCpuPathAndUndoRestores) { check_gpu_path(true); }

TEST(ClayBackend, GpuPathWithClayWhereTheDevicePlacesItEqualsCpuPath) { check_gpu_path(false); }

// Push, pull and smooth strokes with their mirrored and radial copies (compute::sample_sweeps) on the GPU clay kernel
// give the CPU path's model bit for bit, and one undo per stroke takes each stroke back with all its copies.
TEST(ClayBackend, SymmetricClayStrokesOnTheGpuClayKernelEqualTheCpuPath) {
    compute::TriDexel cpu_model = box_model();
    const compute::TriDexel start = cpu_model;
    compute::TriDexel gpu_model = cpu_model;
    auto cpu = make_cpu_backend(cpu_model);
    BackendChoice gpu;
    try {
        gpu = make_boolean_backend(gpu_model, {BackendMode::kGpu, false, true}, false);
    } catch (const tridex::Error& e) {
        GTEST_SKIP() << "no Vulkan device: " << e.what();
    }
    SculptHistory hc(cpu_model, *cpu), hg(gpu_model, *gpu.backend);
    const ToolOp ops[] = {ToolOp::kPush, ToolOp::kPull, ToolOp::kSmooth};
    const char* forms[] = {"x", "radial:4:z", "xy"};
    const Vec3 centre = compute::symmetry_centre(cpu_model.lattice);
    for (int k = 0; k < 3; ++k) {
        ToolSample prev;
        std::vector<compute::Sweep> batch;
        for (int i = 0; i < 24; ++i) {
            ToolSample s;
            // The smooth stroke (k = 2) goes over the push's dent and rim; a flat face gives it nothing to do.
            s.position = Vec3(0.008 + 0.0008 * i, k == 1 ? 0.004 : -0.004, 0.05 + 0.006 - 0.001 - 0.00004 * i);
            s.tool.radius_m = 0.006;
            s.op = ops[k];
            s.symmetry = parse_symmetry(forms[k], "test");
            if (i > 0) compute::sample_sweeps(prev, s, nullptr, nullptr, centre, batch);
            prev = s;
        }
        hc.apply(batch);
        hg.apply(batch);
        hc.end_stroke();
        hg.end_stroke();
        expect_same(cpu_model, gpu_model);
    }
    const compute::GpuClayStats* clay = gpu.backend->gpu_clay_stats();
    ASSERT_NE(clay, nullptr);
    EXPECT_GE(clay->fields, 3u);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NE(hc.undo().serial, 0u);
        EXPECT_NE(hg.undo().serial, 0u);
    }
    expect_same(cpu_model, start);
    expect_same(gpu_model, start);
}

}  // namespace
}  // namespace tridex::app
