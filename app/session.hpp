// app/session.hpp - one sculpting session, shared by `tridex demo` and `tridex replay`: prepare the
// workpiece, run the haptic loop and the sculpt thread with any HapticDevice, render, write outputs.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/boolean_backend.hpp"
#include "app/gpu_contour_share.hpp"
#include "app/sculpt_thread.hpp"
#include "app/session_settings.hpp"
#include "compute/tridexel.hpp"
#include "core/pose.hpp"
#include "core/tri_mesh.hpp"
#include "devices/haptic_device.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app {

/// The placed, scan-converted workpiece.
struct Workpiece {
    std::string mesh_path;          ///< the file it came from
    int resolution = 0;             ///< lattice cells along the longest side
    Mat4 to_world{1.0};             ///< input mesh units -> world metres (uniform scale + translation)
    double volume_mesh_m3 = 0.0;    ///< exact volume of the transformed input mesh
    double volume_dexel_m3 = 0.0;   ///< tri-dexel volume right after scan conversion
    double scan_s = 0.0;            ///< scan-conversion wall time, s
    compute::TriDexel model;        ///< the tri-dexel solid (carved in place by the session)
};

/// Loads `mesh_path` (closed mesh), scales it so its longest side is stock_m and centres it on centre_m
/// (world m), and scan-converts it at `resolution` cells along the longest side. Throws tridex::Error on a
/// bad file, an impossible resolution, or a model that would not fit in memory.
Workpiece prepare_workpiece(const std::string& mesh_path, int resolution, double stock_m, const Vec3& centre_m);

/// The GPU side of a session that contours on the GPU (demo / replay): one Context for the Booleans, the
/// GPU contour and the final render, so that the renderer draws the contour buffers directly. Members are
/// destroyed in reverse order: the contour, then the Booleans, then the Context.
struct SessionGpu {
    std::optional<gpu::Context> context;
    BackendChoice booleans;
    std::unique_ptr<GpuContourShare> contour;  ///< null when the device cannot contour
};

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
    std::uint64_t spilled_intervals = 0;       ///< GPU spill-pool intervals at the end
    std::array<std::size_t, 3> model_bytes{};  ///< model bytes per ray set on the sculpting path
    std::uint32_t sculpt_validation_messages = 0;  ///< Vulkan validation messages on the sculpting device
    std::string contour_path;                  ///< "gpu" (dirty tiles contoured by GpuContourer) or "cpu"
    std::string contour_reason;                ///< why contouring ran on the CPU; "" on the GPU path
    compute::GpuContourStats gpu_contour{};    ///< GPU path: the contourer's counters at the end
    /// The session's Context with its Booleans and (GPU contour path) contour buffers, kept for the final
    /// render; null when the Booleans ran on the CPU.
    std::shared_ptr<SessionGpu> gpu;
};

/// Where a session sculpts.
struct SculptOptions {
    bool cpu = false;       ///< --cpu: the CPU reference even when a Vulkan device exists
    bool validate = false;  ///< Vulkan validation on the sculpting device
    /// --cpu-contour: contour dirty tiles on the CPU even when the Booleans run on the GPU (where a session
    /// supports GPU contouring: `tridex run`).
    bool cpu_contour = false;
    /// --gpu-contour: contour on the GPU even on a CPU Vulkan implementation (lavapipe), where the CPU
    /// Contourer is faster and is the default (gpu_contour_default()).
    bool gpu_contour = false;
};

/// Whether GPU contouring is the default on `context`'s device: true for a real GPU; false for a CPU
/// implementation of Vulkan (VK_PHYSICAL_DEVICE_TYPE_CPU, e.g. Mesa lavapipe), where measured per sculpt step
/// the GPU contour costs 3x the CPU Contourer (5.5 vs 1.6 ms at N = 256) and, sharing one queue with the
/// renderer, limits a live session to one sculpt step per frame. `reason` gets the why when false.
bool gpu_contour_default(const gpu::Context& context, std::string& reason);

/// Runs the haptic loop on `device` with `cfg` and the sculpt thread on wp.model, until the loop has
/// ticked `ticks` times (0: until the device vanishes, e.g. a replay's end) or `timeout_s` of wall time
/// passed; start_m (world m) centres the first active-surface snapshot. The Booleans run on the GPU when a
/// Vulkan device exists and sculpt.cpu is false, else on the CPU (make_boolean_backend). On the GPU path the
/// dirty tiles are contoured on the GPU too (after the active surface is published) unless sculpt.cpu_contour
/// (SessionRun::gpu keeps the buffers for write_session_outputs); the exported mesh (SessionRun::carved) is
/// always the CPU Contourer's, of the final model. Rethrows a
/// sculpt-thread failure; throws tridex::Error when the model does not fit the GPU.
SessionRun run_session(Workpiece& wp, devices::HapticDevice& device, const haptics::HapticLoopConfig& cfg,
                       std::size_t ticks, double timeout_s, const Vec3& start_m, const SculptOptions& sculpt = {});

/// Where and how to write a session's outputs.
struct OutputOptions {
    std::string out;        ///< folder (created)
    int width = 1280;       ///< per-eye image size, px
    int height = 960;
    bool validate = false;  ///< Vulkan validation layer
};

/// Renders both eyes of the carved workpiece (tool at its last position, the haptic workspace as a
/// translucent box and, in bubble mode, the bubble) and writes left.png, right.png, sbs.png, sculpted.ply, haptics.csv and report.json
/// into opt.out, then prints a summary. Throws tridex::Error when a file cannot be written or no Vulkan
/// device is usable.
void write_session_outputs(const OutputOptions& opt, const SessionSettings& settings, const Workpiece& wp,
                           const SessionRun& run,
                           const haptics::HapticLoopConfig& cfg, const devices::DeviceProfile& profile,
                           std::chrono::steady_clock::time_point t_start);

/// Checks the per-eye image size (16..8192 px); throws tridex::Error naming --width/--height.
void check_image_size(int width, int height);

}  // namespace tridex::app
