// app/session/cluster/render_rank.hpp - a render rank of a cluster session: its viewports of the wall, drawn from its
// own replica of the model, in step with rank 0.
#pragma once

#include <string>

#include "app/session/cluster/cluster_config.hpp"
#include "app/session/cluster/cluster_transport.hpp"

namespace tridex::app {

/// How a render rank runs.
struct RenderRankOptions {
    std::string out;          ///< output folder: each offscreen viewport writes out/<viewport name>/ (left, right, output PNGs)
    bool validate = false;    ///< Vulkan validation (a message is counted in the rank's report)
};

/// Runs render rank transport.rank() (>= 1) of `config` until rank 0's last frame: takes the hello (builds the
/// workpiece from the session spec and checks its digest), then per frame applies the records, checks the digest
/// when asked, contours, draws every viewport, answers ready, waits for go and presents. Writes its offscreen
/// viewports' images and answers done with its report. Every failure (a bad message, a record the model refuses,
/// a digest that differs, no Vulkan device, rank 0 silent for longer than the config's timeout) is answered to rank 0
/// when it can be and returned: 0 when the session ended normally, 5 after a failure (said on stderr).
int run_render_rank(ClusterTransport& transport, const ClusterConfig& config, const RenderRankOptions& options);

}  // namespace tridex::app
