// compute/runtime/backend_choice.hpp - the one decision of where a session sculpts: the CPU pool or the GPU compute
// path, by the Vulkan device's type unless --cpu or --gpu forces either.
#pragma once

#include <optional>
#include <string>

#include <vulkan/vulkan.h>

namespace tridex::app {

/// How the sculpting backend is chosen.
enum class BackendMode {
    kAuto,  ///< by the Vulkan device's type: a CPU implementation (lavapipe) -> the CPU pool, a GPU -> compute
    kCpu,   ///< --cpu: the CPU pool whatever the device
    kGpu,   ///< --gpu: the GPU compute path whatever the device's type (an error without a usable device)
};

/// The mode of the flags --cpu and --gpu (neither: kAuto). Throws tridex::Error "--cpu, --gpu: choose one" when
/// both are given.
BackendMode backend_mode(bool cpu, bool gpu);

/// What a session asks of its sculpting backend (the command line's flags).
struct BackendRequest {
    BackendMode mode = BackendMode::kAuto;
    /// --gpu-contour: contour dirty tiles on the GPU, which reads the GPU-resident model: under kAuto it chooses the
    /// compute path on a CPU implementation too.
    bool gpu_contour = false;
    /// --gpu-clay: push, smooth, pull and grab on the GPU clay kernel, which runs on the GPU-resident model: under
    /// kAuto it chooses the compute path on a CPU implementation too.
    bool gpu_clay = false;
};

/// Checks that a request's flags agree: --cpu with --gpu-contour or --gpu-clay asks for GPU work on no GPU model.
/// Throws tridex::Error naming the two flags ("--cpu excludes --gpu-contour ...").
void check_backend_request(const BackendRequest& request);

/// The Vulkan device a session would sculpt on, as far as the decision needs it.
struct SculptDevice {
    /// The device's type (VkPhysicalDeviceProperties::deviceType); nullopt when no Vulkan device is usable.
    std::optional<VkPhysicalDeviceType> type;
    std::string name;   ///< the driver's device name, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string error;  ///< why no device is usable (type nullopt), e.g. the Context's error message
};

/// Where a session sculpts, and why, in one line for report.json `sculpt.backend_reason`.
struct BackendDecision {
    bool gpu = false;    ///< true: the GPU compute path; false: the CPU pool
    std::string reason;  ///< e.g. "auto: the Vulkan device is a CPU implementation (llvmpipe ...)"; never empty
};

/// The one function that decides where every session sculpts (run, demo, replay, study, bench --session: all build
/// their sessions through SessionRuntime, whose Boolean backend comes from make_boolean_backend, which asks this):
///   kCpu -> the CPU pool;
///   kGpu -> the compute path (throws tridex::Error "--gpu: no usable Vulkan device: ..." without a device);
///   kAuto -> no usable device: the CPU pool; a CPU implementation (VK_PHYSICAL_DEVICE_TYPE_CPU): the CPU pool,
///            unless --gpu-contour or --gpu-clay asks for GPU work on the GPU-resident model; a discrete, integrated,
///            virtual or other GPU: the compute path.
/// Throws tridex::Error as check_backend_request for flags that disagree. Pure: no Vulkan call.
BackendDecision decide_backend(const BackendRequest& request, const SculptDevice& device);

/// "a CPU implementation", "a discrete GPU", "an integrated GPU", "a virtual GPU" or "a device of another type".
const char* device_type_phrase(VkPhysicalDeviceType type);

}  // namespace tridex::app
