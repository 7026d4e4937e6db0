// app/scene/session_memory.hpp - the memory a live session of a model will take (the model, its contour at full
// resolution and levels of detail, the renderer's copies), estimated from the model before any of it is built, so that
// a lattice too fine for this machine is refused up front with the memory it would need.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "app/scene/session_spec.hpp"
#include "compute/model/tridexel.hpp"

namespace tridex::app {

/// A live session's memory, estimated from its model (estimate_session_memory).
struct SessionMemory {
    std::size_t model_bytes = 0;      ///< the tri-dexel model as it is (compute::TriDexel::bytes)
    std::uint64_t triangles = 0;      ///< the full-resolution contour's triangles: 4 per interval (below)
    std::size_t contour_bytes = 0;    ///< the contour's meshes, its levels of detail and the renderer's copies
    std::size_t base_bytes = 0;       ///< what a session takes whatever the model (Vulkan, the window, the threads)
    std::size_t total_bytes = 0;      ///< the sum
};

/// Which session the memory is for: they keep different amounts per triangle of the contour.
enum class SessionKind : std::uint8_t {
    kLive,   ///< `tridex run`: the contour's tiles and groups with their levels of detail, the meshes handed to the
             ///< renderer and its vertex buffers (lavapipe keeps them in host memory), windows
    kBatch,  ///< `tridex demo`: the contour at full resolution, drawn offscreen once at the end
};

/// Resident bytes a session holds per triangle of its full-resolution contour, by kind (SessionKind): measured as the
/// peak resident size of `tridex bench --session` (kLive) and `tridex demo` (kBatch) at N = 1024 and 2048 on the
/// bunny, less the model, over the contour's triangles, and rounded up (docs/benchmarks/coarse.md, "Memory").
inline constexpr std::size_t kLiveBytesPerTriangle = 480;
inline constexpr std::size_t kBatchBytesPerTriangle = 220;
/// Resident bytes of a session without its model and contour (Vulkan, the threads, the device), rounded up.
inline constexpr std::size_t kSessionBaseBytes = std::size_t(400) << 20;

/// The session's memory for `model` (its intervals as scan conversion or a .tdx left them). Each interval has two
/// ends; each end is a surface crossing of one lattice edge, and dual contouring makes one quad (two triangles) per
/// crossed edge (Zhang and Leu, tri-dexel contouring), so the full contour has about 4 triangles per interval.
SessionMemory estimate_session_memory(const compute::TriDexel& model, SessionKind kind);

/// Throws tridex::Error naming `what` (e.g. "workpiece.resolution 2048"), the estimate's parts and `available_bytes`
/// when the session would need more than 90 % of them; nothing when it fits, when available_bytes is 0 (unknown),
/// or when the environment sets TRIDEX_IGNORE_MEMORY_ESTIMATE=1 (to try anyway: the estimate is rough).
void check_session_memory(const SessionMemory& need, std::size_t available_bytes, const std::string& what);

/// check_session_memory for a session of kind `kind` of `model`, at lattice resolution `resolution`, against this
/// machine's available memory (available_memory_bytes); named "workpiece.resolution N" in the message.
void check_session_memory_of(const compute::TriDexel& model, int resolution, SessionKind kind);

/// Before a running session of kind `kind` re-samples its `model` onto `resolution` cells along the longest side (a
/// coarseness change): the new model and its contour, estimated as estimate_session_memory's scaled by the square of
/// the resolutions' ratio, against the memory available now plus the current contour's (the new one replaces it; the
/// old model stays, in the undo history). Throws tridex::Error as check_session_memory, named "coarseness N = M";
/// returns the bytes the new model may take (compute::resample_model's max_bytes; SIZE_MAX when the available memory
/// is unknown or the check is turned off).
std::size_t check_resample_memory(const compute::TriDexel& model, int resolution, SessionKind kind);

/// The same before the workpiece is built, for a spec whose workpiece is a mesh scan-converted at more than
/// kMemoryProbeResolution cells: the mesh is scan-converted at that resolution and the estimate scaled by the square of
/// the resolutions' ratio (the contour and the model grow with the surface), so that a lattice too fine is refused
/// before its scan conversion takes the time and the memory. Nothing for a saved model or a study's walls (checked
/// once loaded). Throws tridex::Error as check_session_memory, or as prepare_workpiece for a bad mesh.
void check_session_memory_up_front(const SessionSpec& spec, SessionKind kind);

/// The estimate check_session_memory_up_front makes: a mesh workpiece's session at spec.resolution, from its scan
/// conversion at kMemoryProbeResolution; nullopt for a saved model, a study's walls or a resolution at or below the
/// probe's. Throws tridex::Error as prepare_workpiece (a bad mesh).
std::optional<SessionMemory> estimate_session_memory_of_mesh(const SessionSpec& spec, SessionKind kind);

/// The resolution check_session_memory_up_front scan-converts a mesh at to estimate a finer one.
inline constexpr int kMemoryProbeResolution = 128;

/// Bytes as text for messages: "86 MB", "12.1 GB" (decimal units).
std::string memory_text(std::size_t bytes);

}  // namespace tridex::app
