// gpu/device_clock.hpp - the device's timestamps on the host's steady clock (VK_EXT_calibrated_timestamps).
#pragma once

#include <cstdint>
#include <optional>

#include <vulkan/vulkan.h>

namespace tridex::gpu {

class Context;

/// True when `device`, which offers VK_EXT_calibrated_timestamps (the caller checks that first), can calibrate its
/// timestamps against CLOCK_MONOTONIC, the clock std::chrono::steady_clock reads on Linux: both the device and the
/// CLOCK_MONOTONIC time domains are calibrateable. `instance` is the instance `device` belongs to. False when either
/// domain is missing or the query fails; never throws.
bool can_calibrate_timestamps(VkInstance instance, VkPhysicalDevice device);

/// Converts a timestamp the device wrote (a query result, in ticks of VkPhysicalDeviceLimits::timestampPeriod ns,
/// `valid_mask` its valid bits) to the host's steady clock, in seconds of std::chrono::steady_clock's epoch. It
/// calibrates afresh at each call (one vkGetCalibratedTimestampsEXT of the device and CLOCK_MONOTONIC) and takes the
/// timestamp as the calibration's device tick plus its signed distance from it, so a timestamp written before or
/// after the calibration both convert. Returns nullopt when the Context did not enable the extension
/// (DeviceFeatures::calibrated_timestamps false) or the call fails; never throws.
std::optional<double> device_ticks_to_steady_s(const Context& context, std::uint64_t ticks, std::uint64_t valid_mask);

}  // namespace tridex::gpu
