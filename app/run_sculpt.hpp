// app/run_sculpt.hpp - the haptic loop and the sculpt thread of a `tridex run` session, running while the
// render thread draws (DESIGN.md, "three threads, one direction of flow").
#pragma once

#include <chrono>
#include <cstddef>
#include <memory>

#include "app/gpu_contour_share.hpp"
#include "app/run_scene.hpp"
#include "app/sculpt_thread.hpp"
#include "app/session.hpp"
#include "compute/contour_dual.hpp"
#include "core/active_surface.hpp"
#include "core/spsc_ring.hpp"
#include "core/tool_sample.hpp"
#include "core/triple_buffer.hpp"
#include "devices/simulated_device.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app {

/// The sculpting side of a run: the scene's workpiece scan-converted and contoured, a simulated device whose
/// virtual hand follows the scripted stroke (plan_stroke; or holds still in front of the workpiece when the
/// scene has none), the 1 kHz HapticLoop on it and the SculptThread carving the model and publishing the
/// contoured mesh for the renderer (SculptThread::publish_mesh_to, throttled to mesh_interval_s). The render
/// thread reads latest_view() and latest_mesh(): newest values, never waiting for either thread, and neither
/// thread ever waits for it. One render thread; not movable (the threads hold references into it).
class SculptBackend {
public:
    /// Prepares everything (loads, scan-converts and contours the workpiece, plans the stroke, checks the loop
    /// configuration) without starting threads. Throws tridex::Error for a bad mesh, an impossible resolution,
    /// a stroke with no material under it or a bad loop configuration.
    /// `form`: how the contoured surface is handed over (MeshFrame: the whole mesh or per-tile meshes).
    /// `booleans`: where the swept Booleans run (the GPU by default when a Vulkan device exists; --cpu).
    /// `render_context`: the renderer's Context. When given and the Booleans run on the GPU, they run on it
    /// (one Context for both threads), and, unless booleans.cpu_contour, `form` is kWhole or the device is a CPU implementation of Vulkan
    /// without booleans.gpu_contour (gpu_contour_default), the dirty tiles are contoured on
    /// the GPU into gpu_contour() for the renderer to draw (else, or when the device cannot contour, the CPU
    /// Contourer with contour_reason() saying why).
    explicit SculptBackend(const RunScene& scene, double mesh_interval_s = 1.0 / 60.0,
                           MeshForm form = MeshForm::kTiles, const SculptOptions& booleans = {},
                           gpu::Context* render_context = nullptr);
    /// Stops the threads if they run (errors of the sculpt thread are then dropped: call stop() to see them).
    ~SculptBackend();
    SculptBackend(const SculptBackend&) = delete;
    SculptBackend& operator=(const SculptBackend&) = delete;

    /// Starts the sculpt thread, then the haptic loop.
    void start();
    /// Stops the haptic loop, then the sculpt thread (which drains every sample and publishes the final mesh).
    /// Rethrows a sculpt-thread failure. Idempotent.
    void stop();

    /// The newest LoopView (render thread only).
    const haptics::LoopView& latest_view() { return loop_->latest_view(); }
    /// The newest contoured mesh (render thread only); valid until the next call.
    const MeshFrame& latest_mesh() { return meshes_.latest(); }
    /// True once the haptic loop has played the whole stroke (device time; never for a scene without stroke)
    /// or has ended by itself (device lost).
    bool stroke_done() const;
    /// False once the haptic loop ended by itself.
    bool loop_running() const { return loop_->running(); }

    /// Where the tool is drawn before the loop's first tick, and the device workspace box there (world m).
    Vec3 start_tool_m() const { return start_m_; }
    Aabb start_box_m() const;

    /// Where the Booleans run (path, device, spill-pool use) and why.
    const BackendChoice& booleans() const { return booleans_; }
    /// The GPU contour the renderer draws (lock_frame), or nullptr when contouring runs on the CPU.
    GpuContourShare* gpu_contour() { return gpu_contour_.get(); }
    /// "gpu" or "cpu": where dirty tiles are contoured.
    std::string contour_path() const { return gpu_contour_ ? "gpu" : "cpu"; }
    /// Why contouring runs on the CPU ("" on the GPU path), e.g. "--cpu-contour given".
    const std::string& contour_reason() const { return contour_reason_; }
    const Workpiece& workpiece() const { return wp_; }                 ///< the model (read after stop())
    const haptics::HapticLoopConfig& config() const { return cfg_; }  ///< the loop configuration
    const devices::DeviceProfile& profile() const { return profile_; } ///< the simulated device's profile
    haptics::LoopStats loop_stats() const { return loop_->stats(); }  ///< loop counters (any time)
    const SculptStats& sculpt_stats() const { return sculpt_->stats(); }  ///< after stop()
    std::size_t stroke_ticks() const { return stroke_ticks_; }        ///< ticks the stroke lasts; 0 without stroke
    std::size_t tiles_initial() const { return tiles_initial_; }      ///< tiles contoured before the session
    double contour_s() const { return contour_s_; }                   ///< initial contouring wall time, s
    double session_s() const { return session_s_; }                   ///< start() .. stop() wall time, s (after stop())

private:
    Workpiece wp_;
    devices::DeviceProfile profile_;
    haptics::HapticLoopConfig cfg_;
    Vec3 start_m_{0.0};
    std::size_t stroke_ticks_ = 0, tiles_initial_ = 0;
    double contour_s_ = 0.0, session_s_ = 0.0;
    std::chrono::steady_clock::time_point t_start_{};
    bool started_ = false, stopped_ = false;
    std::unique_ptr<compute::Contourer> contourer_;
    std::unique_ptr<SpscRing<ToolSample>> ring_;
    TripleBuffer<ActiveSurface> surface_;
    TripleBuffer<MeshFrame> meshes_;
    std::unique_ptr<devices::SimulatedDevice> device_;
    BackendChoice booleans_;  // before sculpt_: the thread uses it
    std::unique_ptr<GpuContourShare> gpu_contour_;  // after booleans_ (its slabs), before sculpt_ (uses it)
    std::string contour_reason_;
    std::unique_ptr<SculptThread> sculpt_;
    std::unique_ptr<haptics::HapticLoop> loop_;
};

}  // namespace tridex::app
