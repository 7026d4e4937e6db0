// app/session/batch/session.hpp - one sculpting session, shared by `tridex demo` and `tridex replay`: prepare the
// workpiece, run the haptic loop and the sculpt thread with any HapticDevice, render, write outputs.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/support/output_dir.hpp"
#include "app/session/runtime/session_runtime.hpp"
#include "app/scene/session_spec.hpp"
#include "compute/model/tridexel.hpp"
#include "core/pose.hpp"
#include "core/tri_mesh.hpp"
#include "devices/haptic_device.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app {

/// What a session produced.
struct SessionRun {
    std::vector<haptics::TickRecord> records;  ///< one per haptic tick
    haptics::LoopStats loop{};                 ///< loop counters
    SculptStats sculpt;                        ///< sculpt-thread counters
    std::size_t tiles_initial = 0;             ///< tiles contoured before the session
    double contour_s = 0.0;                    ///< initial contouring wall time, s
    double session_s = 0.0;                    ///< wall time of the session, s
    double volume_after_m3 = 0.0;              ///< tri-dexel volume after the session
    TriMesh carved;                            ///< the contoured model after the session, world m
    std::vector<std::uint8_t> carved_materials;  ///< material id per carved vertex (Contourer::mesh_materials)
    haptics::LoopView last_view;               ///< the loop's last published view (tool, workspace box, bubble)
    std::string sculpt_path;                   ///< "gpu" or "cpu"
    std::string sculpt_device;                 ///< Vulkan device name on the GPU path
    std::string sculpt_path_reason;            ///< why the CPU path ran; "" on the GPU path
    std::string sculpt_backend_reason;         ///< why this backend, either path (BackendChoice::reason)
    std::string clay_path;                     ///< "gpu" or "cpu": where clay sweeps ran (BooleanBackend::clay_path)
    std::string clay_path_reason;              ///< why clay ran on the CPU on the GPU path; "" otherwise
    std::uint64_t spilled_intervals = 0;       ///< GPU spill-pool intervals at the end
    std::array<std::size_t, 3> model_bytes{};  ///< model bytes per ray set on the sculpting path
    std::uint32_t sculpt_validation_messages = 0;  ///< Vulkan validation messages on the sculpting device
    std::string contour_path;                  ///< "gpu" (dirty tiles contoured by GpuContourer) or "cpu"
    std::string contour_reason;                ///< why contouring ran on the CPU; "" on the GPU path
    compute::GpuContourStats gpu_contour{};    ///< GPU path: the contourer's counters at the end
    std::optional<compute::JournalStats> journal;  ///< the session journal's counters (SculptOptions::journal)
    /// The session's threads, stopped: its Context (context()) and, on the GPU contour path, its contour
    /// buffers serve the final render.
    std::unique_ptr<SessionRuntime> runtime;
    /// "SIGINT" or "SIGTERM" when a signal ended the session early (its outputs are still written), else "".
    std::string stopped_by;
    /// When the device went away before the session's end (its read failed while ticks were still due): the device
    /// time of the last good tick, s. Unset otherwise (a replay's recording running out is its normal end).
    std::optional<double> device_lost_at_s;
    /// Clay sessions (op push, smooth, pull or grab): the largest distance between the surface before and after the session, m
    /// (compute::clay_max_displacement_cells); set by the caller that kept the model before.
    std::optional<double> deformation_max_displacement_m;
};

/// Runs the session of `spec` (device_origin_m set) on wp.model with `device`: builds a SessionRuntime (the
/// Booleans on the GPU when a Vulkan device exists and sculpt.cpu is false, else on the CPU; dirty tiles
/// contoured on the GPU where that is the default or asked for), starts it, and stops it once the loop has
/// ticked `ticks` times (0: until the device vanishes, e.g. a replay's end) or `timeout_s` of wall time
/// passed, keeping at most `max_records` tick records; start_m (world m) centres the first active-surface snapshot. The exported mesh
/// (SessionRun::carved) is always the CPU Contourer's, of the final model. `loop`: a replay's additions to the
/// loop configuration (RuntimeOptions::loop). `more`: spec.more_workpieces prepared (prepare_more_workpieces),
/// sculpted beside the first. Rethrows a sculpt-thread failure;
/// throws tridex::Error when the model does not fit the GPU or the spec is refused.
SessionRun run_session(const SessionSpec& spec, Workpiece wp, std::unique_ptr<devices::HapticDevice> device,
                       std::size_t ticks, std::size_t max_records, double timeout_s, const Vec3& start_m,
                       const SculptOptions& sculpt = {}, const LoopOverrides& loop = {}, std::vector<Workpiece> more = {});

/// The files write_session_outputs writes into the output folder (demo and replay check them against their other
/// outputs before the session).
inline constexpr std::array<const char*, 6> kSessionOutputFiles = {"left.png",     "right.png",   "sbs.png",
                                                                    "sculpted.ply", "haptics.csv", "report.json"};

/// Where and how to write a session's outputs.
struct OutputOptions {
    std::string out;        ///< folder (created)
    int width = 1280;       ///< per-eye image size, px
    int height = 960;
    bool validate = false;  ///< Vulkan validation layer
    bool ao = true;         ///< ambient occlusion in the images (SceneView::occlusion_strength 1, else 0)
    std::string command = "demo";  ///< the command that ran, for the summary's first line ("tridex demo: ...")
};

/// Renders both eyes of the carved workpiece, framed by framing_screen (tool at its last position, the haptic
/// workspace as a translucent box and, in bubble mode, the bubble) and writes left.png, right.png, sbs.png, sculpted.ply, haptics.csv and report.json
/// (and, for each further workpiece k, its sculpted-wp<k+1>.ply, in its model frame)
/// into opt.out, each through `writes` (a file that cannot be written is said at once and costs no other; the
/// report lists the files written and notes the others), then prints a summary. The caller writes its other outputs
/// through `writes` too and then calls writes.finish(). Throws tridex::Error when no Vulkan device is usable.
/// The session's spec, workpiece, loop configuration and device profile come from run.runtime.
void write_session_outputs(const OutputOptions& opt, SessionRun& run, std::chrono::steady_clock::time_point t_start,
                           OutputWrites& writes);

/// Checks the per-eye image size (16..8192 px); throws tridex::Error naming --width/--height.
void check_image_size(int width, int height);

/// Parses a per-eye image size "WxH" (pixels, e.g. "1280x720") and checks it as check_image_size does.
/// Throws tridex::Error naming `option` when the text is not two positive integers joined by 'x' or is out of range.
std::pair<int, int> parse_image_size(const std::string& text, const std::string& option);

}  // namespace tridex::app
