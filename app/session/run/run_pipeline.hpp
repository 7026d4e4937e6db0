// app/session/run/run_pipeline.hpp - one live session of `tridex run`, in steps: the display and its stereo sink, the head and
// navigation inputs, the sculpting threads, the frame loop, and the outputs.
#pragma once

#include <memory>
#include <vector>

#include "app/session/run/run_session.hpp"
#include "app/session/runtime/session_companion.hpp"

namespace tridex::app {

/// One run session, built from its options and driven by one frame loop. Window, fullscreen and offscreen differ
/// only in the stereo sink the frames go to (renderer/output/stereo_sink.hpp).
///
/// The steps, in order: open() refuses what the display cannot show before any other work (GPU, window, sink,
/// renderer), then makes the head provider, navigation and wand, then the sculpting threads (SculptBackend: the
/// workpiece, the haptic loop, the sculpt thread); run() drives frames on the calling thread (GLFW needs the
/// main thread) until Esc or window close, --frames, --seconds, the end of the stroke or scripted cursor
/// (offscreen), the study's end cap, a stop signal or the offscreen safety net; then it stops the threads,
/// collects the counters and writes the outputs (images, sculpted.ply, recording, --save, report.json).
class RunPipeline {
public:
    /// Resolves the options (resolve_run) and opens every part of the session, with `companions` beside it
    /// (they must outlive the pipeline). Throws tridex::Error on bad options or scene, no usable Vulkan device or
    /// display, or an output the display cannot show.
    explicit RunPipeline(const RunOptions& options, std::vector<SessionCompanion*> companions = {});
    ~RunPipeline();
    RunPipeline(const RunPipeline&) = delete;
    RunPipeline& operator=(const RunPipeline&) = delete;

    /// Runs the frames, stops the session and writes its outputs; returns what the run did. Throws tridex::Error
    /// when an output could not be written (after writing every other one and report.json), the sculpt thread
    /// failed, or a companion failed (after writing every output). Call once.
    RunResult run();

private:
    struct Parts;
    std::unique_ptr<Parts> p_;
};

}  // namespace tridex::app
