// renderer/stereo/draw_batching.hpp - runs of like draws (per-tile meshes sharing one pool buffer) merged into
// one multi-draw indirect command.
#pragma once

#include <cstdint>
#include <vector>

#include "gpu/buffer.hpp"
#include "gpu/context.hpp"
#include "renderer/stereo/eye_strategy.hpp"
#include "renderer/stereo/stereo_frame.hpp"

namespace tridex::renderer {

/// True when the device offers multiDrawIndirect and drawIndirectFirstInstance (gpu::Context enables both
/// whenever they are offered).
bool multi_draw_supported(const gpu::Context& context);

/// Merges runs of consecutive, direct (non-indirect) draws that bind the same pipeline kind, buffers and push
/// constants into one StereoDraw drawn by a single vkCmdDrawIndexedIndirect of several commands
/// (StereoDraw::indirect_count > 1), so that a frame of thousands of tile draws records a few draws. The
/// commands carry each draw's firstIndex, vertexOffset and, for EyeStrategy::kInstancedLayer, the instances of
/// its eye mask (both eyes: 2 from 0; one eye: 1 from that eye); so runs may mix eye masks there and under
/// multiview (which draws every view anyway), while pass-per-eye merges only draws of one eye mask.
/// Owns a host-visible command buffer per instance: use one per frame in flight (it is rewritten by batch()).
/// Needs the device features multiDrawIndirect and drawIndirectFirstInstance (multi_draw_supported); without
/// them batch() leaves the draws as they are. Move-only.
class DrawBatcher {
public:
    /// Rewrites `draws` in place (list order kept) with runs of at least 2 mergeable draws replaced by one
    /// indirect draw each (at most maxDrawIndirectCount commands), writing their commands into this batcher's
    /// buffer (grown as needed; the GPU must be done with the previous frame that used this batcher).
    /// `eye_count` 1 (mono: only the left eye's part of each mask counts) or 2, as given to record_stereo_frame.
    /// Returns the number of draws merged away. Throws tridex::Error on a Vulkan failure growing the buffer.
    std::size_t batch(const gpu::Context& context, EyeStrategy strategy, int eye_count, std::vector<StereoDraw>& draws);

private:
    gpu::Buffer commands_;
};

}  // namespace tridex::renderer
