// compute/model/model_digest.cpp - FNV-1a over a model's rays and intervals.
#include "compute/model/model_digest.hpp"

#include <bit>
#include <cstdio>

namespace tridex::compute {

namespace {

constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ull;
constexpr std::uint64_t kFnvPrime = 0x100000001b3ull;

// Folds the 4 bytes of v (little-endian order) into h.
inline std::uint64_t fold32(std::uint64_t h, std::uint32_t v) {
    for (int b = 0; b < 4; ++b) {
        h ^= (v >> (8 * b)) & 0xffu;
        h *= kFnvPrime;
    }
    return h;
}

}  // namespace

std::uint64_t model_digest(const TriDexel& model) {
    std::uint64_t h = kFnvOffset;
    for (const RaySet& set : model.sets) {
        h = fold32(h, static_cast<std::uint32_t>(set.nu));
        h = fold32(h, static_cast<std::uint32_t>(set.nv));
        for (const std::vector<Interval>& ray : set.rays) {
            h = fold32(h, static_cast<std::uint32_t>(ray.size()));
            for (const Interval& iv : ray) {
                h = fold32(h, std::bit_cast<std::uint32_t>(iv.enter));
                h = fold32(h, std::bit_cast<std::uint32_t>(iv.exit));
                h = fold32(h, static_cast<std::uint32_t>(iv.enter_material) | (static_cast<std::uint32_t>(iv.exit_material) << 8));
            }
        }
    }
    return h;
}

std::string digest_hex(std::uint64_t digest) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(digest));
    return text;
}

}  // namespace tridex::compute
