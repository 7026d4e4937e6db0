// renderer/stereo/draw_batching.cpp - consecutive like draws -> one vkCmdDrawIndexedIndirect.
#include "renderer/stereo/draw_batching.hpp"

#include <algorithm>
#include <cstring>

namespace tridex::renderer {
namespace {

// True when b can join a run that a starts: same pipeline, bindings and push constants, both direct and
// non-empty, and (pass per eye, which filters draws per pass by their mask) the same eyes.
bool same_state(const StereoDraw& a, const StereoDraw& b, EyeStrategy strategy, std::uint32_t eyes_drawn) {
    if (a.indirect != VK_NULL_HANDLE || b.indirect != VK_NULL_HANDLE) return false;
    if (a.index_count == 0 || b.index_count == 0) return false;
    if ((a.eye_mask & eyes_drawn) == 0 || (b.eye_mask & eyes_drawn) == 0) return false;
    if (strategy == EyeStrategy::kPassPerEye && (a.eye_mask & eyes_drawn) != (b.eye_mask & eyes_drawn)) return false;
    return a.kind == b.kind && a.vertices == b.vertices && a.indices == b.indices &&
           std::memcmp(&a.constants, &b.constants, sizeof(DrawConstants)) == 0;
}

}  // namespace

bool multi_draw_supported(const gpu::Context& context) {
    return context.features().multi_draw_indirect && context.features().draw_indirect_first_instance;
}

std::size_t DrawBatcher::batch(const gpu::Context& context, EyeStrategy strategy, int eye_count,
                               std::vector<StereoDraw>& draws) {
    const std::uint32_t max_count = context.properties().limits.maxDrawIndirectCount;
    if (!multi_draw_supported(context) || max_count < 2 || draws.size() < 2) return 0;
    const std::uint32_t eyes_drawn = eye_count == 1 ? 0b01u : 0b11u;
    std::vector<VkDrawIndexedIndirectCommand> commands;
    std::vector<StereoDraw> out;
    std::vector<std::size_t> merged_at;  // indices into `out` of the merged draws
    out.reserve(draws.size());
    for (std::size_t i = 0; i < draws.size();) {
        std::size_t j = i + 1;
        while (j < draws.size() && j - i < max_count && same_state(draws[i], draws[j], strategy, eyes_drawn)) ++j;
        if (j - i < 2) {
            out.push_back(draws[i++]);
            continue;
        }
        StereoDraw m = draws[i];
        m.indirect_offset = commands.size() * sizeof(VkDrawIndexedIndirectCommand);
        m.indirect_count = static_cast<std::uint32_t>(j - i);
        m.eye_mask = 0;
        std::uint64_t indices = 0;
        for (std::size_t k = i; k < j; ++k) {
            const StereoDraw& d = draws[k];
            const std::uint32_t mask = d.eye_mask & eyes_drawn;
            VkDrawIndexedIndirectCommand c{d.index_count, 1, d.first_index, d.vertex_offset, 0};
            if (strategy == EyeStrategy::kInstancedLayer) {  // as record_stereo_frame draws a direct draw
                c.instanceCount = mask == 0b11u ? 2u : 1u;
                c.firstInstance = mask == 0b10u ? 1u : 0u;
            }
            commands.push_back(c);
            m.eye_mask |= mask;
            indices += d.index_count;
        }
        m.index_count = static_cast<std::uint32_t>(std::min<std::uint64_t>(indices, UINT32_MAX));
        merged_at.push_back(out.size());
        out.push_back(m);
        i = j;
    }
    if (commands.empty()) return 0;
    const VkDeviceSize bytes = commands.size() * sizeof(VkDrawIndexedIndirectCommand);
    if (commands_.size() < bytes)
        commands_ = gpu::Buffer::create(context, std::max<VkDeviceSize>(bytes, 2 * commands_.size()),
                                        VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, gpu::MemoryDomain::kHost);
    commands_.write(commands.data(), bytes);
    for (const std::size_t k : merged_at) out[k].indirect = commands_.handle();
    const std::size_t merged = draws.size() - out.size();
    draws.swap(out);
    return merged;
}

}  // namespace tridex::renderer
