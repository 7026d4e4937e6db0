// app/session/cluster/cluster_config.hpp - the cluster config of a wall driven by several machines: which rank draws
// which part of the wall (a projector tile, its eye or eyes) and where it shows it.
#pragma once

#include <string>
#include <vector>

#include "renderer/camera/display_config.hpp"
#include "renderer/camera/stereo_output_mode.hpp"

namespace tridex::app {

/// Which eye a viewport shows.
enum class ViewportEye {
    kBoth,   ///< both eyes, through the viewport's stereo output (side by side, quad, frame-sequential, ...)
    kLeft,   ///< the left eye only (one projector of a passive pair): a mono view from the left eye
    kRight,  ///< the right eye only
};

/// Where a viewport's frames go.
enum class ViewportOutput {
    kOffscreen,   ///< nothing shown; the last frame is written as PNGs (tests, previews)
    kWindow,      ///< a window on the rank's display
    kFullscreen,  ///< fullscreen on one monitor of the rank's display (a projector)
};

/// One projector tile of the wall, drawn by one rank.
struct ClusterViewport {
    std::string name;                 ///< unique in the config; names its output folder
    renderer::Screen screen;          ///< the tile's corners in wall space (the display config's frame), m
    int width_px = 0, height_px = 0;  ///< per-eye image size, px
    ViewportEye eye = ViewportEye::kBoth;
    renderer::StereoOutput stereo = renderer::StereoOutput::kMono;  ///< the output of a kBoth viewport
    ViewportOutput output = ViewportOutput::kOffscreen;
    int monitor = 0;                  ///< kFullscreen: the monitor's index on the rank's display
    bool swap_eyes = false;           ///< exchange the eyes on this projector (default: the display config's)
    renderer::AnaglyphMethod anaglyph = renderer::AnaglyphMethod::kDubois;  ///< the display config's
    double refresh_hz = 60.0;         ///< the display config's (frame-sequential pacing)
};

/// A render rank's share of the wall.
struct ClusterRank {
    int rank = 1;                              ///< MPI rank, >= 1 (rank 0 runs the session)
    std::vector<ClusterViewport> viewports;    ///< at least one
};

/// A cluster config file (docs/formats/cluster-config.md).
struct ClusterConfig {
    std::string source;                ///< the file it was read from
    std::vector<ClusterRank> ranks;    ///< ranks 1..K, each once, in rank order
    int check_every_frames = 30;       ///< frames between model digest checks, 1..100000
    double timeout_s = 10.0;           ///< a rank that does not answer within this long has failed, s, (0, 3600]
    double start_timeout_s = 120.0;    ///< the same for the first frame (ranks load the workpiece), s, (0, 3600]
    /// Levels of detail on the render ranks, as `run --lod`: "on" (simplified levels below
    /// compute::kCoarseGroupsFromCells cells, groups contoured from the dexels from there), "coarse", "simplified"
    /// or "off" (every tile at full resolution).
    std::string lod = "on";
    /// How a render rank starts where its groups take coarse levels (lod "on" from compute::kCoarseGroupsFromCells
    /// cells, or "coarse"), as `run --startup`: "coarse" (the coarsest group levels drawn at once, tiles contoured
    /// where frames need them; ClusterReplica's coarse_first) or "full" (every tile contoured before the first frame).
    std::string startup = "coarse";
    /// How a render rank draws a stroke where its groups take coarse levels, as `run --stroke-contour`: "coarse" (the
    /// stroke's tiles wait while it is open and the coarse group levels over them stand in, finer where a frame
    /// needs it; ClusterReplica's stroke_coarse) or "full" (the changed tiles its viewports see are contoured in
    /// the frame that brings them).
    std::string stroke_contour = "coarse";
    /// A wall without mpirun (ClusterTransport over the network): the key that seals its link, from a key file (32
    /// bytes or 64 hex digits; a relative path is taken from the config's folder) or the name of an environment
    /// variable holding a passphrase, the same on every rank; both "" = the link is not sealed.
    std::string key_file;
    std::string passphrase_env;  ///< see key_file

    /// The viewports of `rank`, or nullptr when it has none.
    const ClusterRank* find(int rank) const;
};

/// Reads a cluster config: {"ranks": [{"rank": 1, "viewports": [{"name", "region": [x0, y0, x1, y1] (fractions of
/// the wall's screen, left to right and bottom to top) or "corners": {"lower_left", "lower_right", "upper_left"} (m,
/// wall space), "width_px", "height_px" (default: the display's pixels times the region's share), "eye" (both | left
/// | right), "stereo" (a stereo output name; default the display's), "output" (offscreen | window | fullscreen),
/// "monitor", "swap_eyes" (default the display's)}]}], "check_every_frames", "timeout_s", "start_timeout_s", "lod",
/// "startup", "stroke_contour", "key_file", "passphrase_env"}. `display` is the wall's display config (its screen, resolution and
/// stereo output supply the defaults). Throws tridex::Error naming the file and field:
/// unreadable or not JSON, unknown fields, ranks missing (they must be 1..K, each once), a viewport with no
/// area or corners not at right angles, duplicate viewport names, values out of range.
ClusterConfig read_cluster_config(const std::string& path, const renderer::DisplayConfig& display);

/// The same from JSON text already read; `source` names it in messages.
ClusterConfig parse_cluster_config(const std::string& text, const std::string& source, const renderer::DisplayConfig& display);

}  // namespace tridex::app
