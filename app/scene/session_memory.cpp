// app/scene/session_memory.cpp - a live session's memory, estimated from its model.
#include "app/scene/session_memory.hpp"

#include <cstdio>
#include <cstdlib>
#include <limits>

#include "app/support/memory.hpp"
#include "app/scene/workpiece_source.hpp"
#include "compute/tools/model_resample.hpp"
#include "core/error.hpp"

namespace tridex::app {

namespace {
std::size_t bytes_per_triangle(SessionKind kind) {
    return kind == SessionKind::kLive ? kLiveBytesPerTriangle : kBatchBytesPerTriangle;
}
bool estimate_ignored() {
    const char* v = std::getenv("TRIDEX_IGNORE_MEMORY_ESTIMATE");
    return v && std::string(v) == "1";
}
}  // namespace

SessionMemory estimate_session_memory(const compute::TriDexel& model, SessionKind kind) {
    SessionMemory m;
    std::size_t intervals = 0;
    for (const compute::RaySet& set : model.sets) {
        m.model_bytes += set.rays.size() * sizeof(std::vector<compute::Interval>);
        for (const std::vector<compute::Interval>& ray : set.rays) {
            m.model_bytes += ray.capacity() * sizeof(compute::Interval);
            intervals += ray.size();
        }
    }
    m.triangles = 4u * static_cast<std::uint64_t>(intervals);
    m.contour_bytes = static_cast<std::size_t>(m.triangles) * bytes_per_triangle(kind);
    m.base_bytes = kSessionBaseBytes;
    m.total_bytes = m.model_bytes + m.contour_bytes + m.base_bytes;
    return m;
}

std::string memory_text(std::size_t bytes) {
    char text[32];
    if (bytes >= 1000000000u)
        std::snprintf(text, sizeof text, "%.1f GB", static_cast<double>(bytes) / 1e9);
    else
        std::snprintf(text, sizeof text, "%.0f MB", static_cast<double>(bytes) / 1e6);
    return text;
}

void check_session_memory(const SessionMemory& need, std::size_t available_bytes, const std::string& what) {
    if (available_bytes == 0) return;
    if (estimate_ignored()) return;
    if (static_cast<double>(need.total_bytes) <= 0.9 * static_cast<double>(available_bytes)) return;
    char tri[32];
    std::snprintf(tri, sizeof tri, "%.1f million", static_cast<double>(need.triangles) / 1e6);
    throw Error(what + ": this session would need about " + memory_text(need.total_bytes) + " (the model " +
                memory_text(need.model_bytes) + ", its contour of about " + tri + " triangles with its levels of "
                "detail and the renderer's copies " + memory_text(need.contour_bytes) + ", the rest " +
                memory_text(need.base_bytes) + "); this machine has " + memory_text(available_bytes) +
                " available. Lower workpiece.resolution (the memory grows with its square), close other programs, "
                "or set TRIDEX_IGNORE_MEMORY_ESTIMATE=1 to try anyway");
}

void check_session_memory_of(const compute::TriDexel& model, int resolution, SessionKind kind) {
    check_session_memory(estimate_session_memory(model, kind), available_memory_bytes(),
                         "workpiece.resolution " + std::to_string(resolution));
}

std::size_t check_resample_memory(const compute::TriDexel& model, int resolution, SessionKind kind) {
    const SessionMemory now = estimate_session_memory(model, kind);
    const double k = static_cast<double>(resolution) / compute::lattice_resolution(model.lattice);
    SessionMemory need;
    need.model_bytes = static_cast<std::size_t>(static_cast<double>(now.model_bytes) * k * k);
    need.triangles = static_cast<std::uint64_t>(static_cast<double>(now.triangles) * k * k);
    need.contour_bytes = static_cast<std::size_t>(need.triangles) * bytes_per_triangle(kind);
    need.total_bytes = need.model_bytes + need.contour_bytes;
    const std::size_t available = available_memory_bytes();
    if (available == 0) return std::numeric_limits<std::size_t>::max();
    check_session_memory(need, available + now.contour_bytes, "coarseness N = " + std::to_string(resolution));
    if (estimate_ignored()) return std::numeric_limits<std::size_t>::max();
    return available + now.contour_bytes;
}

std::optional<SessionMemory> estimate_session_memory_of_mesh(const SessionSpec& spec, SessionKind kind) {
    if (!spec.study_model.empty() || !spec.model_path.empty() || spec.mesh_path.empty()) return std::nullopt;
    if (spec.resolution <= kMemoryProbeResolution) return std::nullopt;
    // Milliseconds at this resolution, so its progress step prints nothing.
    const Workpiece probe = prepare_workpiece(spec.mesh_path, kMemoryProbeResolution, spec.stock_m, spec.workpiece_centre_m);
    const SessionMemory p = estimate_session_memory(probe.model, kind);
    const double k = static_cast<double>(spec.resolution) / kMemoryProbeResolution;
    SessionMemory m;
    m.model_bytes = static_cast<std::size_t>(static_cast<double>(p.model_bytes) * k * k);
    m.triangles = static_cast<std::uint64_t>(static_cast<double>(p.triangles) * k * k);
    m.contour_bytes = static_cast<std::size_t>(m.triangles) * bytes_per_triangle(kind);
    m.base_bytes = p.base_bytes;
    m.total_bytes = m.model_bytes + m.contour_bytes + m.base_bytes;
    return m;
}

void check_session_memory_up_front(const SessionSpec& spec, SessionKind kind) {
    if (const std::optional<SessionMemory> m = estimate_session_memory_of_mesh(spec, kind))
        check_session_memory(*m, available_memory_bytes(), "workpiece.resolution " + std::to_string(spec.resolution));
}

}  // namespace tridex::app
