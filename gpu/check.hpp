// gpu/check.hpp - turning a failed VkResult into a tridex::Error that names the call.
#pragma once

#include <vulkan/vulkan.h>

namespace tridex::gpu {

/// The enumerator name of a core VkResult ("VK_ERROR_OUT_OF_DEVICE_MEMORY"); "unrecognised VkResult"
/// for codes outside Vulkan 1.2 core.
const char* result_name(VkResult result);

/// Throws tridex::Error("Vulkan: <call> failed: <result name> (<number>)") when result is negative (an error
/// code); returns result unchanged otherwise (VK_SUCCESS, VK_TIMEOUT, VK_INCOMPLETE, ...).
VkResult check(VkResult result, const char* call);

}  // namespace tridex::gpu
