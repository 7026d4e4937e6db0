// renderer/timing/frame_stats.hpp - what one stereo frame cost and what it drew.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace tridex::renderer {

/// Workpiece tiles one eye drew and skipped (outside its frustum) in one frame.
struct EyeTileCounts {
    std::size_t drawn = 0;
    std::size_t skipped = 0;
};

/// Where FrameStats times come from.
enum class TimingSource {
    kGpuTimestamps,  ///< timestamp queries on the queue (ticks * VkPhysicalDeviceLimits::timestampPeriod)
    kCpuClock,       ///< steady_clock around the submission and its wait (no per-pass split)
};

/// Time of one pass of a frame: "opaque", "translucent" or "overlay" (or "frame" for CPU timing).
struct PassTime {
    std::string pass;
    int eye = -1;      ///< 0 left, 1 right; -1 when one render pass serves both eyes (multiview, instanced-layer)
    double ms = 0.0;   ///< milliseconds
};

/// Per-frame statistics returned by OffscreenStereoRenderer::draw() / render().
struct FrameStats {
    std::array<EyeTileCounts, 2> tiles{};  ///< per eye (0 left, 1 right); zeros when the scene has no tiles
    std::size_t tile_uploads = 0;          ///< tile meshes and levels uploaded this frame (drawn and new or changed)
    /// Workpiece tile triangles drawn per eye (0 left, 1 right), at the levels of detail chosen (the indirect
    /// workpiece's tiles at full resolution).
    std::array<std::size_t, 2> tile_triangles{};
    /// Groups of tiles (SceneView::tile_groups) drawn per eye at one of their levels in place of their tiles.
    std::array<std::size_t, 2> groups_drawn{};
    /// Of those, the groups an eye drew with their own triangles only, without ring and skirt (groups_drawn_own_only).
    std::array<std::size_t, 2> groups_own_only{};
    /// Ids (TileGroup::id) of the visible groups an eye drew over its pixel bound because nothing under them could
    /// draw their surface yet (wants_detail), ascending: where the frames want full-resolution tiles.
    std::vector<std::uint64_t> groups_wanting_detail;
    /// Ids (TileGroup::id) of the groups an eye chose a level for within the pixel bound (not standing in over it),
    /// visible or not, ascending: nothing under them was needed (compute::DrawnGroups).
    std::vector<std::uint64_t> groups_at_level;
    /// Draws recorded (each StereoDraw once, whatever the eyes), and how many more there were before runs of
    /// like draws were merged into one multi-draw indirect command each (DrawBatcher; 0 without the feature).
    std::size_t draws = 0;
    std::size_t draws_merged = 0;
    TimingSource timing = TimingSource::kGpuTimestamps;
    std::string timing_note;               ///< one line: the timing source, and why when it is the CPU clock
    /// GPU: every phase of every render pass instance ("occlusion" only when the frame ran the ambient occlusion);
    /// CPU: one "frame".
    std::vector<PassTime> passes;
    double frame_ms = -1.0;                ///< whole frame incl. readback copy (GPU), or submit + wait (CPU)
    /// The renderer's count of frames drawn when this one was submitted (1 for the first frame).
    std::uint64_t frame = 0;
    /// When the device finished this frame, s on std::chrono::steady_clock's epoch (its bottom-of-pipe timestamp,
    /// calibrated to the host: gpu/device_clock.hpp); NaN without calibrated timestamps or before it finished.
    double gpu_end_s = std::numeric_limits<double>::quiet_NaN();

    /// Sum of `pass`'s times over the eyes/passes, ms; -1 when no entry has that name.
    double pass_ms(std::string_view pass) const {
        double sum = 0.0;
        bool any = false;
        for (const PassTime& p : passes)
            if (p.pass == pass) {
                sum += p.ms;
                any = true;
            }
        return any ? sum : -1.0;
    }
};

}  // namespace tridex::renderer
