// renderer/stereo/stereo_frame.cpp - command recording of a stereo frame.
#include "renderer/stereo/stereo_frame.hpp"

#include <cstring>

namespace tridex::renderer {

DrawPhase phase_of(PipelineKind kind) {
    switch (kind) {
        case PipelineKind::kOpaque:
        case PipelineKind::kContour: return DrawPhase::kOpaque;
        case PipelineKind::kTranslucentBack:
        case PipelineKind::kTranslucentFront: return DrawPhase::kTranslucent;
        case PipelineKind::kOverlay: return DrawPhase::kOverlay;
    }
    return DrawPhase::kOpaque;
}

const char* timed_phase_name(int k) {
    static const char* const kNames[kTimedPhaseCount] = {"opaque", "occlusion", "translucent", "overlay"};
    return k >= 0 && k < kTimedPhaseCount ? kNames[k] : "";
}

namespace {

// The timestamp boundary before draw phase `phase` (opaque 0; translucent and overlay after the occlusion part).
int boundary_before(int phase) { return phase == 0 ? 0 : phase + 1; }

}  // namespace

void record_stereo_frame(VkCommandBuffer cmd, const StereoPipeline& pipeline, const StereoTarget& target,
                         VkDescriptorSet eyes, std::span<const StereoDraw> draws, const float clear_rgba[4],
                         const PhaseTimestamps& timestamps, int eye_count, const AmbientOcclusion* occlusion,
                         const std::array<PixelRect, 2>& occlusion_regions, bool readback,
                         OcclusionResolution occlusion_resolution) {
    const auto w = static_cast<std::uint32_t>(target.width());
    const auto h = static_cast<std::uint32_t>(target.height());
    VkClearValue clears[2]{};
    for (int c = 0; c < 4; ++c) clears[0].color.float32[c] = clear_rgba[c];
    clears[1].depthStencil = {1.0f, 0};
    const VkViewport viewport{0.0f, 0.0f, static_cast<float>(w), static_cast<float>(h), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, {w, h}};
    const EyeStrategy strategy = pipeline.strategy();
    const bool per_eye = strategy == EyeStrategy::kPassPerEye;
    const VkShaderStageFlags push_stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;

    const bool mono = eye_count == 1;
    const std::uint32_t eyes_drawn = mono ? 0b01u : 0b11u;
    const auto& framebuffers = target.framebuffers();
    const std::size_t passes = per_eye && mono ? 1 : framebuffers.size();
    // Draws of phases first..last of render pass instance `pass` (timestamps at their boundaries).
    const auto record_phases = [&](std::size_t pass, int first, int last) {
        vkCmdSetViewport(cmd, 0, 1, &viewport);
        vkCmdSetScissor(cmd, 0, 1, &scissor);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.layout(), 0, 1, &eyes, 0, nullptr);
        VkPipeline bound = VK_NULL_HANDLE;
        // Push constants and buffers stay bound from draw to draw (every pipeline has the one layout): only
        // changes are recorded, which spares a CPU implementation (lavapipe) state updates per tile draw.
        DrawConstants pushed{};
        bool any_pushed = false;
        VkBuffer bound_vertices = VK_NULL_HANDLE, bound_indices = VK_NULL_HANDLE;
        const auto push = [&](const DrawConstants& c) {
            if (any_pushed && std::memcmp(&pushed, &c, sizeof c) == 0) return;
            vkCmdPushConstants(cmd, pipeline.layout(), push_stages, 0, sizeof(DrawConstants), &c);
            pushed = c;
            any_pushed = true;
        };
        for (int phase = first; phase <= last; ++phase) {
            if (timestamps.pool != VK_NULL_HANDLE)
                vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timestamps.pool,
                                    timestamps.query(pass, boundary_before(phase)));
            for (const StereoDraw& d : draws) {
                if (d.index_count == 0 || static_cast<int>(phase_of(d.kind)) != phase) continue;
                const std::uint32_t mask = d.eye_mask & eyes_drawn;
                if (mask == 0 || (per_eye && !(mask & (1u << pass)))) continue;
                std::uint32_t instances = 1, first_instance = 0;
                if (strategy == EyeStrategy::kInstancedLayer) {
                    instances = mask == 0b11u ? 2u : 1u;
                    first_instance = mask == 0b10u ? 1u : 0u;
                }
                const VkPipeline p = pipeline.pipeline(d.kind);
                if (p != bound) {
                    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p);
                    bound = p;
                }
                DrawConstants constants = d.constants;
                constants.eye = per_eye ? static_cast<std::uint32_t>(pass) : 0u;
                constants.eye_mask = mask;
                const VkDeviceSize offset = 0;
                if (d.vertices != bound_vertices) {
                    vkCmdBindVertexBuffers(cmd, 0, 1, &d.vertices, &offset);
                    bound_vertices = d.vertices;
                }
                if (d.indices != bound_indices) {
                    vkCmdBindIndexBuffer(cmd, d.indices, 0, VK_INDEX_TYPE_UINT32);
                    bound_indices = d.indices;
                }
                if (d.indirect != VK_NULL_HANDLE && d.indirect_count > 0) {  // a run: the commands carry the eyes
                    push(constants);
                    vkCmdDrawIndexedIndirect(cmd, d.indirect, d.indirect_offset, d.indirect_count, kIndirectCommandBytes);
                    continue;
                }
                if (d.indirect != VK_NULL_HANDLE && strategy == EyeStrategy::kInstancedLayer) {
                    // The command's instanceCount is 1: one draw per eye, the eye in the push constant.
                    for (std::uint32_t e = 0; e < 2; ++e) {
                        if (!(mask & (1u << e))) continue;
                        constants.eye = e;
                        push(constants);
                        vkCmdDrawIndexedIndirect(cmd, d.indirect, d.indirect_offset, 1, kIndirectCommandBytes);
                    }
                    continue;
                }
                push(constants);
                if (d.indirect != VK_NULL_HANDLE)
                    vkCmdDrawIndexedIndirect(cmd, d.indirect, d.indirect_offset, 1, kIndirectCommandBytes);
                else
                    vkCmdDrawIndexed(cmd, d.index_count, instances, d.first_index, d.vertex_offset, first_instance);
            }
        }
    };
    const auto begin_pass = [&](VkRenderPass render_pass, std::size_t pass) {
        VkRenderPassBeginInfo begin{};
        begin.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO;
        begin.renderPass = render_pass;
        begin.framebuffer = framebuffers[pass].get();
        begin.renderArea = scissor;
        begin.clearValueCount = 2;
        begin.pClearValues = clears;
        vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
    };
    // Per render pass instance: the opaque phase, ambient occlusion of its layers, then translucent and overlay.
    const auto opaque = static_cast<int>(DrawPhase::kOpaque);
    for (std::size_t pass = 0; pass < passes; ++pass) {
        begin_pass(pipeline.render_pass(), pass);
        record_phases(pass, opaque, opaque);
        if (timestamps.pool != VK_NULL_HANDLE)
            vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timestamps.pool, timestamps.query(pass, 1));
        vkCmdEndRenderPass(cmd);
        if (occlusion != nullptr) {
            if (per_eye)
                occlusion->record(cmd, static_cast<std::uint32_t>(pass), 1, occlusion_regions[pass],
                                  occlusion_resolution);
            else
                occlusion->record(cmd, 0, mono ? 1u : 2u,
                                  mono ? occlusion_regions[0] : unite(occlusion_regions[0], occlusion_regions[1]),
                                  occlusion_resolution);
        }
        begin_pass(pipeline.resume_pass(), pass);
        record_phases(pass, opaque + 1, kDrawPhaseCount - 1);
        if (timestamps.pool != VK_NULL_HANDLE)
            vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timestamps.pool,
                                timestamps.query(pass, kTimedPhaseCount));
        vkCmdEndRenderPass(cmd);
    }
    // Render pass instances not recorded (mono, pass-per-eye): their boundaries, zero duration; and their
    // layers go to TRANSFER_SRC_OPTIMAL (contents undefined) as the render pass would have left them, after
    // earlier submissions' transfer reads (an execution dependency suffices for that write-after-read).
    for (std::size_t pass = passes; pass < framebuffers.size(); ++pass) {
        if (timestamps.pool != VK_NULL_HANDLE)
            for (int b = 0; b <= kTimedPhaseCount; ++b)
                vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timestamps.pool,
                                    timestamps.query(pass, b));
        VkImageMemoryBarrier layer{};
        layer.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
        layer.srcAccessMask = 0;
        layer.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        layer.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        layer.newLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        layer.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        layer.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        layer.image = target.colour_image();
        layer.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, static_cast<std::uint32_t>(pass), 1};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0,
                             nullptr, 1, &layer);
    }

    if (readback) record_readback(cmd, target, eye_count);
}

void record_readback(VkCommandBuffer cmd, const StereoTarget& target, int eye_count) {
    const auto w = static_cast<std::uint32_t>(target.width());
    const auto h = static_cast<std::uint32_t>(target.height());
    VkBufferImageCopy copy{};
    copy.bufferOffset = 0;
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, eye_count == 1 ? 1u : 2u};
    copy.imageExtent = {w, h, 1};
    vkCmdCopyImageToBuffer(cmd, target.colour_image(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target.readback_buffer(),
                           1, &copy);
    VkMemoryBarrier barrier{};
    barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr,
                         0, nullptr);
}

}  // namespace tridex::renderer
