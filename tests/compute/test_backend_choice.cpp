// Where a session sculpts (decide_backend): every device type against every flag combination, and the refusals;
// make_boolean_backend on the device here (lavapipe in the tests) follows the decision.
#include <gtest/gtest.h>

#include <string>

#include "compute/runtime/backend_choice.hpp"
#include "compute/runtime/boolean_backend.hpp"
#include "compute/model/tridexel.hpp"
#include "core/error.hpp"
#include "gpu/context.hpp"

namespace tridex::app {
namespace {

SculptDevice device_of(VkPhysicalDeviceType type) { return SculptDevice{type, "dev", ""}; }
SculptDevice no_device() { return SculptDevice{std::nullopt, "", "no Vulkan loader"}; }

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

TEST(BackendChoice, FlagsGiveTheMode) {
    EXPECT_EQ(backend_mode(false, false), BackendMode::kAuto);
    EXPECT_EQ(backend_mode(true, false), BackendMode::kCpu);
    EXPECT_EQ(backend_mode(false, true), BackendMode::kGpu);
    try {
        backend_mode(true, true);
        FAIL() << "--cpu with --gpu must be refused";
    } catch (const Error& e) {
        EXPECT_TRUE(has(e.what(), "--cpu, --gpu: choose one")) << e.what();
    }
}

TEST(BackendChoice, AutoFollowsTheDeviceType) {
    const BackendRequest autom{};
    const BackendDecision cpu = decide_backend(autom, SculptDevice{VK_PHYSICAL_DEVICE_TYPE_CPU, "llvmpipe (LLVM 15)", ""});
    EXPECT_FALSE(cpu.gpu);
    EXPECT_EQ(cpu.reason, "auto: the Vulkan device is a CPU implementation (llvmpipe (LLVM 15))");
    for (const VkPhysicalDeviceType t : {VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU,
                                         VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU, VK_PHYSICAL_DEVICE_TYPE_OTHER}) {
        const BackendDecision d = decide_backend(autom, device_of(t));
        EXPECT_TRUE(d.gpu) << t;
        EXPECT_EQ(d.reason, std::string("auto: the Vulkan device is ") + device_type_phrase(t) + " (dev)");
    }
    EXPECT_TRUE(has(decide_backend(autom, device_of(VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU)).reason, "a discrete GPU"));
    EXPECT_TRUE(has(decide_backend(autom, device_of(VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU)).reason, "an integrated GPU"));
    const BackendDecision none = decide_backend(autom, no_device());
    EXPECT_FALSE(none.gpu);
    EXPECT_EQ(none.reason, "auto: no usable Vulkan device: no Vulkan loader");
}

TEST(BackendChoice, GpuContourAndGpuClayChooseTheComputePathOnACpuImplementation) {
    for (const bool contour : {false, true})
        for (const bool clay : {false, true}) {
            const BackendRequest r{BackendMode::kAuto, contour, clay};
            const BackendDecision d = decide_backend(r, device_of(VK_PHYSICAL_DEVICE_TYPE_CPU));
            EXPECT_EQ(d.gpu, contour || clay) << contour << clay;
            if (contour) {
                EXPECT_TRUE(has(d.reason, "--gpu-contour")) << d.reason;
            } else if (clay) {
                EXPECT_TRUE(has(d.reason, "--gpu-clay")) << d.reason;
            }
            // On a GPU they change nothing; without a device the CPU pool still runs.
            EXPECT_TRUE(decide_backend(r, device_of(VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU)).gpu);
            EXPECT_FALSE(decide_backend(r, no_device()).gpu);
        }
}

TEST(BackendChoice, CpuAndGpuForceEitherOnEveryDevice) {
    for (const VkPhysicalDeviceType t : {VK_PHYSICAL_DEVICE_TYPE_CPU, VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU,
                                         VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU, VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU,
                                         VK_PHYSICAL_DEVICE_TYPE_OTHER}) {
        const BackendDecision c = decide_backend({BackendMode::kCpu}, device_of(t));
        EXPECT_FALSE(c.gpu);
        EXPECT_EQ(c.reason, "--cpu given");
        for (const bool contour : {false, true})
            for (const bool clay : {false, true}) {
                const BackendDecision g = decide_backend({BackendMode::kGpu, contour, clay}, device_of(t));
                EXPECT_TRUE(g.gpu);
                EXPECT_TRUE(has(g.reason, "--gpu given; the Vulkan device is ")) << g.reason;
            }
    }
    EXPECT_FALSE(decide_backend({BackendMode::kCpu}, no_device()).gpu);
    try {
        decide_backend({BackendMode::kGpu}, no_device());
        FAIL() << "--gpu without a device must be refused";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), "--gpu: no usable Vulkan device: no Vulkan loader");
    }
}

TEST(BackendChoice, CpuWithGpuContourOrGpuClayIsRefused) {
    for (const bool contour : {false, true})
        for (const bool clay : {false, true}) {
            const BackendRequest r{BackendMode::kCpu, contour, clay};
            if (!contour && !clay) {
                EXPECT_NO_THROW(check_backend_request(r));
                continue;
            }
            try {
                decide_backend(r, device_of(VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU));
                FAIL() << "--cpu with a GPU flag must be refused";
            } catch (const Error& e) {
                EXPECT_TRUE(has(e.what(), contour ? "--cpu excludes --gpu-contour" : "--cpu excludes --gpu-clay")) << e.what();
            }
        }
}

// The backend make_boolean_backend builds is the one decided for the device here.
TEST(BackendChoice, MakeBooleanBackendFollowsTheDecision) {
    std::optional<gpu::Context> ctx;
    try {
        ctx.emplace(gpu::Context::create({}));
    } catch (const Error& e) {
        GTEST_SKIP() << "no Vulkan device: " << e.what();
    }
    const bool cpu_device = ctx->properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    compute::Lattice lattice;
    lattice.cell_m = 1e-3;
    lattice.cells = {8, 8, 8};
    for (const BackendMode mode : {BackendMode::kAuto, BackendMode::kCpu, BackendMode::kGpu}) {
        compute::TriDexel model = compute::TriDexel::empty(lattice, std::size_t{1} << 20);
        const BackendChoice shared = make_boolean_backend_on(model, {mode}, *ctx);
        const bool want_gpu = mode == BackendMode::kGpu || (mode == BackendMode::kAuto && !cpu_device);
        EXPECT_EQ(shared.backend->path(), want_gpu ? "gpu" : "cpu") << shared.reason;
        EXPECT_EQ(shared.reason, decide_backend({mode}, {ctx->properties().deviceType, ctx->device_name(), ""}).reason);
        EXPECT_EQ(shared.cpu_reason(), want_gpu ? "" : shared.reason);
        compute::TriDexel model2 = compute::TriDexel::empty(lattice, std::size_t{1} << 20);
        const BackendChoice own = make_boolean_backend(model2, {mode}, false);
        EXPECT_EQ(own.backend->path(), want_gpu ? "gpu" : "cpu") << own.reason;
        EXPECT_FALSE(own.reason.empty());
    }
}

}  // namespace
}  // namespace tridex::app
