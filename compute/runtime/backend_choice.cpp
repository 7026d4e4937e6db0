// compute/runtime/backend_choice.cpp - where a session sculpts: the rules, in one place.
#include "compute/runtime/backend_choice.hpp"

#include "core/error.hpp"

namespace tridex::app {

BackendMode backend_mode(bool cpu, bool gpu) {
    if (cpu && gpu) throw Error("--cpu, --gpu: choose one (--cpu sculpts on the CPU pool, --gpu on the GPU compute path)");
    return cpu ? BackendMode::kCpu : gpu ? BackendMode::kGpu : BackendMode::kAuto;
}

void check_backend_request(const BackendRequest& r) {
    if (r.mode != BackendMode::kCpu) return;
    if (r.gpu_contour)
        throw Error("--cpu excludes --gpu-contour: the GPU contour reads the model on the GPU compute path");
    if (r.gpu_clay) throw Error("--cpu excludes --gpu-clay: the GPU clay kernel runs on the GPU compute path");
}

const char* device_type_phrase(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return "a CPU implementation";
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "a discrete GPU";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "an integrated GPU";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "a virtual GPU";
        default: return "a device of another type";
    }
}

BackendDecision decide_backend(const BackendRequest& r, const SculptDevice& device) {
    check_backend_request(r);
    if (r.mode == BackendMode::kCpu) return {false, "--cpu given"};
    if (!device.type) {
        if (r.mode == BackendMode::kGpu) throw Error("--gpu: no usable Vulkan device: " + device.error);
        return {false, "auto: no usable Vulkan device: " + device.error};
    }
    const std::string what = std::string("the Vulkan device is ") + device_type_phrase(*device.type) + " (" + device.name + ")";
    if (r.mode == BackendMode::kGpu) return {true, "--gpu given; " + what};
    if (*device.type != VK_PHYSICAL_DEVICE_TYPE_CPU) return {true, "auto: " + what};
    if (r.gpu_contour) return {true, "auto: " + what + ", but --gpu-contour needs the model on the GPU compute path"};
    if (r.gpu_clay) return {true, "auto: " + what + ", but --gpu-clay needs the model on the GPU compute path"};
    return {false, "auto: " + what};
}

}  // namespace tridex::app
