// renderer/stereo/stereo_frame.hpp - recording one stereo frame's draws for any eye strategy.
#pragma once

#include <cstddef>
#include <array>
#include <cstdint>
#include <span>

#include <vulkan/vulkan.h>

#include "renderer/stereo/ambient_occlusion.hpp"
#include "renderer/stereo/stereo_pipeline.hpp"
#include "renderer/stereo/stereo_target.hpp"
#include "renderer/stereo/stereo_uniforms.hpp"

namespace tridex::renderer {

/// One indexed draw (uint32 indices, MeshVertex vertices) seen by the eyes in eye_mask.
struct StereoDraw {
    PipelineKind kind = PipelineKind::kOpaque;
    VkBuffer vertices = VK_NULL_HANDLE;
    VkBuffer indices = VK_NULL_HANDLE;
    std::uint32_t index_count = 0;
    std::uint32_t first_index = 0;   ///< first index read from `indices` (vkCmdDrawIndexed firstIndex)
    std::int32_t vertex_offset = 0;  ///< added to each index (vkCmdDrawIndexed vertexOffset)
    DrawConstants constants;  ///< `eye` is overwritten per pass for kPassPerEye
    /// Eyes that draw it: bit 0 left, bit 1 right (0b11 both; 0 none). Pass-per-eye honours it per pass;
    /// instanced-layer draws only the masked instances (first instance = eye); multiview cannot draw one
    /// view only, so a non-zero mask draws in both views.
    std::uint32_t eye_mask = 0b11;
    /// Not null: draw with vkCmdDrawIndexedIndirect from the one VkDrawIndexedIndirectCommand at
    /// indirect_offset (bytes) of this buffer (its instanceCount must be 1) instead of index_count indices
    /// from index 0; index_count must then be non-zero (the command's count, or any non-zero value) or the
    /// draw is skipped. Instanced-layer draws it once per masked eye with constants.eye set (shaders that
    /// take the eye from the push constant: PipelineKind::kContour).
    VkBuffer indirect = VK_NULL_HANDLE;
    VkDeviceSize indirect_offset = 0;
    /// With `indirect`: 0 = the one-command convention above; n >= 1 = n consecutive commands drawn by one
    /// vkCmdDrawIndexedIndirect, each carrying the instanceCount / firstInstance the strategy needs (DrawBatcher:
    /// instanced-layer 2 from 0 for both eyes, 1 from the eye for one; others 1 from 0). Needs the device's
    /// multiDrawIndirect (n > 1) and drawIndirectFirstInstance features.
    std::uint32_t indirect_count = 0;
};

/// The timed phases of a render pass instance, in drawing order: opaque (kOpaque), translucent
/// (kTranslucentBack, kTranslucentFront), overlay (kOverlay).
enum class DrawPhase { kOpaque = 0, kTranslucent = 1, kOverlay = 2 };
constexpr int kDrawPhaseCount = 3;

/// Stride of VkDrawIndexedIndirectCommand records, bytes.
constexpr std::uint32_t kIndirectCommandBytes = 20;

/// The phase a pipeline kind belongs to.
DrawPhase phase_of(PipelineKind kind);

/// The timed parts of a render pass instance, in order: the opaque draws, the ambient-occlusion dispatch that
/// follows them (zero duration without it), the translucent draws and the overlay draws. Timed part k runs from
/// boundary k to boundary k + 1 (PhaseTimestamps).
constexpr int kTimedPhaseCount = 4;

/// Name of timed part k (0..kTimedPhaseCount-1): "opaque", "occlusion", "translucent", "overlay".
const char* timed_phase_name(int k);

/// Where record_stereo_frame() writes phase timestamps: in render pass instance p, boundary b (0 = before
/// the opaque draws, 1 = after them, 2 = before translucent (after the ambient-occlusion dispatch), 3 = before
/// overlay, 4 = after overlay) goes to query first_query + (p * (kTimedPhaseCount + 1) + b) * stride. stride is
/// the number of queries one timestamp takes: 2 inside a multiview render pass (one per view, Vulkan spec
/// vkCmdWriteTimestamp), else 1 (every boundary is written inside a render pass instance). The caller resets
/// those queries before recording and reads them after the submission completes.
struct PhaseTimestamps {
    VkQueryPool pool = VK_NULL_HANDLE;
    std::uint32_t first_query = 0;
    std::uint32_t stride = 1;
    /// Query index of boundary `boundary` (0..kTimedPhaseCount) of render pass instance `pass`.
    std::uint32_t query(std::size_t pass, int boundary) const {
        return first_query + (static_cast<std::uint32_t>(pass) * (kTimedPhaseCount + 1u) +
                              static_cast<std::uint32_t>(boundary)) * stride;
    }
};

/// Records into `cmd` (in the recording state): per render pass instance of the strategy over `target`, the
/// opaque phase in pipeline.render_pass() (clearing colour to `clear_rgba` (linear, 0..1) and depth to 1), then
/// `occlusion`'s dispatches over that instance's layers (none when `occlusion` is null) within
/// `occlusion_regions` (per eye, pixels that may hold opaque surface; an instance drawing both eyes uses the
/// union of the two) at `occlusion_resolution`, then the translucent and
/// overlay phases in pipeline.resume_pass(); `draws` for both eyes grouped by phase
/// (opaque, then translucent, then overlay; list order kept within a phase), each as its eye_mask allows
/// (pass-per-eye: once per pass whose eye is in the mask, constants.eye = pass; multiview: once, the view
/// mask replicates it; instanced-layer: instances for the masked eyes), then, when `readback`, the copy of the
/// colour layers into the target's readback buffer followed by a transfer -> host barrier (record_readback). `eyes` is a descriptor set for
/// pipeline.set_layout() holding the EyesUniform. With `timestamps` (pool not null) it writes a
/// bottom-of-pipe timestamp at each phase boundary of every render pass instance (see PhaseTimestamps).
/// `eye_count` 1 = mono, one eye's work only: only the left eye (layer 0) is drawn and copied back
/// (pass-per-eye: the right eye's render pass is not recorded and its timestamps are written back to back,
/// zero duration, so every query of the pool is available; instanced-layer: one instance per draw; multiview:
/// its render pass always covers both views, so the right view is still drawn there); layer 1 keeps its old
/// contents. Any other value than 1 draws both eyes.
void record_stereo_frame(VkCommandBuffer cmd, const StereoPipeline& pipeline, const StereoTarget& target,
                         VkDescriptorSet eyes, std::span<const StereoDraw> draws, const float clear_rgba[4],
                         const PhaseTimestamps& timestamps = {}, int eye_count = 2,
                         const AmbientOcclusion* occlusion = nullptr,
                         const std::array<PixelRect, 2>& occlusion_regions = {}, bool readback = true,
                         OcclusionResolution occlusion_resolution = OcclusionResolution::kHalf);

/// Records the copy of the target's colour layers (layer 0 only when eye_count == 1; they must be in
/// TRANSFER_SRC_OPTIMAL with the frame's writes visible to transfer reads, as record_stereo_frame leaves them)
/// into its readback buffer, followed by a transfer -> host barrier (StereoTarget::read_layer afterwards).
void record_readback(VkCommandBuffer cmd, const StereoTarget& target, int eye_count);

}  // namespace tridex::renderer
