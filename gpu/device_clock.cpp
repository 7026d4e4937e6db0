// gpu/device_clock.cpp - calibrated timestamps: the device's ticks on the host's steady clock.
#include "gpu/device_clock.hpp"

#include <algorithm>
#include <chrono>
#include <type_traits>
#include <vector>

#include "gpu/context.hpp"

namespace tridex::gpu {

namespace {

// std::chrono::steady_clock is CLOCK_MONOTONIC in glibc's libstdc++: the host domain the device is calibrated against.
static_assert(std::is_same_v<std::chrono::steady_clock::duration, std::chrono::nanoseconds>);
constexpr VkTimeDomainEXT kHostDomain = VK_TIME_DOMAIN_CLOCK_MONOTONIC_EXT;

}  // namespace

bool can_calibrate_timestamps(VkInstance instance, VkPhysicalDevice device) {
    const auto domains_of = reinterpret_cast<PFN_vkGetPhysicalDeviceCalibrateableTimeDomainsEXT>(
        vkGetInstanceProcAddr(instance, "vkGetPhysicalDeviceCalibrateableTimeDomainsEXT"));
    if (!domains_of) return false;
    std::uint32_t count = 0;
    if (domains_of(device, &count, nullptr) != VK_SUCCESS) return false;
    std::vector<VkTimeDomainEXT> domains(count);
    if (domains_of(device, &count, domains.data()) != VK_SUCCESS) return false;
    const auto has = [&](VkTimeDomainEXT d) { return std::find(domains.begin(), domains.end(), d) != domains.end(); };
    return has(VK_TIME_DOMAIN_DEVICE_EXT) && has(kHostDomain);
}

std::optional<double> device_ticks_to_steady_s(const Context& context, std::uint64_t ticks, std::uint64_t valid_mask) {
    if (!context.features().calibrated_timestamps || valid_mask == 0) return std::nullopt;
    const auto calibrate = reinterpret_cast<PFN_vkGetCalibratedTimestampsEXT>(
        vkGetDeviceProcAddr(context.device(), "vkGetCalibratedTimestampsEXT"));
    if (!calibrate) return std::nullopt;
    VkCalibratedTimestampInfoEXT info[2]{};
    for (VkCalibratedTimestampInfoEXT& i : info) i.sType = VK_STRUCTURE_TYPE_CALIBRATED_TIMESTAMP_INFO_EXT;
    info[0].timeDomain = VK_TIME_DOMAIN_DEVICE_EXT;
    info[1].timeDomain = kHostDomain;
    std::uint64_t now[2]{}, deviation = 0;
    if (calibrate(context.device(), 2, info, now, &deviation) != VK_SUCCESS) return std::nullopt;
    // The signed distance from the calibration's device tick, modulo the valid bits (a timestamp may have wrapped).
    const std::uint64_t ahead = (ticks - now[0]) & valid_mask;
    const std::uint64_t half = valid_mask / 2 + 1;
    const double delta_ticks =
        ahead < half ? static_cast<double>(ahead) : -static_cast<double>((now[0] - ticks) & valid_mask);
    const double period_ns = context.properties().limits.timestampPeriod;
    return (static_cast<double>(now[1]) + delta_ticks * period_ns) * 1e-9;
}

}  // namespace tridex::gpu
