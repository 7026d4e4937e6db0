// compute/runtime/detail_requests.hpp - what the frames drew and where they want more detail than the coarse group
// levels give: the render thread offers tile groups (drawn, or drawn over the pixel bound), the sculpt thread reads
// them (which levels to rebuild during a stroke; which tiles to contour).
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <span>
#include <vector>

namespace tridex::compute {

/// Requests for full-resolution tiles, from the frames to the sculpt thread's coarse-first refinement
/// (SculptThread::refine_on_demand). Each is a tile group id (compute::tile_group_id) that a frame drew at a level
/// whose error projects over its pixel bound because nothing under it could draw its surface yet
/// (renderer::FrameStats::groups_wanting_detail). Thread-safe: any thread offers, one takes.
class DetailRequests {
public:
    /// Most ids held: further offers are dropped until take() (frames offer them again).
    static constexpr std::size_t kMaxIds = 4096;
    /// Adds `group_ids` to those waiting (duplicates kept once).
    void offer(std::span<const std::uint64_t> group_ids);
    /// The ids offered since the last take, ascending and unique (finest depth first: the depth is the id's top
    /// byte); empties the set.
    std::vector<std::uint64_t> take();

private:
    std::mutex mutex_;
    std::vector<std::uint64_t> ids_;
};

/// The tile groups frames drew at one of their levels within the pixel bound (renderer::FrameStats::groups_at_level,
/// each frame's offered whole; the sculpt thread takes the union of those since its last take), from the render
/// thread to the sculpt thread (SculptThread::follow_drawn_groups): the same mailbox as DetailRequests, each id a
/// compute::tile_group_id. Thread-safe: any thread offers, one takes.
using DrawnGroups = DetailRequests;

}  // namespace tridex::compute
