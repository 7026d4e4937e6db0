// compute/runtime/sculpt_thread.cpp - the sculpt thread loop.
#include "compute/runtime/sculpt_thread.hpp"

#include <chrono>
#include <cmath>
#include <utility>

#include "compute/runtime/gpu_contour_share.hpp"
#include "compute/runtime/active_surface_publish.hpp"
#include "compute/tools/sweep.hpp"
#include "core/error.hpp"
#include "core/thread_name.hpp"

namespace tridex::app {

namespace {
// Re-centre the active surface when the tool has moved this many cells from the window centre,
// even without a model change (a window is ActiveSurface::kWindow rays wide).
constexpr double kRecentreCells = 4.0;
}  // namespace

SculptThread::SculptThread(compute::TriDexel& model, compute::Contourer& contourer, SpscRing<ToolSample>& samples,
                           TripleBuffer<ActiveSurface>& surface, const Vec3& start_m, double tool_radius_m,
                           double tool_span_m)
    : model_(model), own_backend_(make_cpu_backend(model)), backend_(own_backend_.get()), contourer_(contourer),
      samples_(samples), surface_(surface), published_centre_m_(start_m) {
    if (!is_finite(start_m)) throw Error("SculptThread: start position is not finite");
    if (!std::isfinite(tool_radius_m) || tool_radius_m < 0.0 || !std::isfinite(tool_span_m) || tool_span_m < 0.0)
        throw Error("SculptThread: tool_radius_m and tool_span_m must be finite and >= 0");
    tool_radius_m_ = tool_radius_m;
    tool_span_m_ = tool_span_m;
    publish(start_m);
}

SculptThread::~SculptThread() {
    try {
        stop();
    } catch (...) {
        // A failure nobody collected with stop(): the thread is joined; a destructor must not throw.
    }
}

void SculptThread::use_mesh_tools(std::vector<std::shared_ptr<const compute::MeshTool>> tools) {
    if (thread_.joinable()) throw Error("SculptThread::use_mesh_tools: call it before start()");
    mesh_tools_ = std::move(tools);
}

std::shared_ptr<const compute::MeshTool> SculptThread::mesh_tool(std::uint32_t id) const {
    if (id >= mesh_tools_.size())
        throw Error("tool sample: mesh tool " + std::to_string(id) + " is not in the session's table of " +
                    std::to_string(mesh_tools_.size()));
    return mesh_tools_[id];
}

void SculptThread::use_backend(BooleanBackend& backend) {
    if (thread_.joinable()) throw Error("SculptThread::use_backend: call it before start()");
    backend_ = &backend;
}

void SculptThread::use_gpu_contour(GpuContourShare& share) {
    if (thread_.joinable()) throw Error("SculptThread::use_gpu_contour: call it before start()");
    gpu_contour_ = &share;
}

void SculptThread::start() {
    if (thread_.joinable()) throw Error("SculptThread::start: already running");
    stop_.store(false);
    failure_ = nullptr;
    thread_ = std::thread([this] {
        name_this_thread("tridex-sculpt");
        run();
    });
}

void SculptThread::stop() {
    if (!thread_.joinable()) return;
    stop_.store(true);
    thread_.join();
    if (failure_) std::rethrow_exception(std::exchange(failure_, nullptr));
}

void SculptThread::run() {
    for (;;) {
        const bool stopping = stop_.load(std::memory_order_acquire);
        bool worked = false;
        if (failure_) {  // failed earlier: keep the ring drained so the producer never sees it full
            ToolSample s;
            while (samples_.try_pop(s)) worked = true;
        } else {
            try {
                worked = step();
            } catch (...) {
                failure_ = std::current_exception();
                worked = true;
            }
        }
        if (!failure_) {
            try {
                publish_mesh_if_due(stopping && !worked);  // the last state always reaches the renderer
            } catch (...) {
                failure_ = std::current_exception();
            }
        }
        if (stopping && !worked) return;  // the ring was drained after stop was asked
        if (!worked) std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
}

bool SculptThread::step() {
    const auto t0 = std::chrono::steady_clock::now();
    ToolSample s;
    bool any = false, changed = false;
    batch_.clear();
    while (samples_.try_pop(s)) {
        any = true;
        ++stats_.samples;
        if (have_prev_ && s.op != ToolOp::kNone && s.tool.radius_m > 0.0) {
            compute::Sweep sw;
            sw.op = s.op;
            sw.tool = compute::sweep_tool(s.tool, s.tool.kind == ToolKind::kMesh ? mesh_tool(s.tool.mesh_id) : nullptr);
            sw.axis = s.orientation * tool_axis_local();  // the sample's axis over its whole segment
            if (s.tool.kind == ToolKind::kMesh) sw.orientation = s.orientation;  // the mesh turns with roll too
            sw.path_m = Segment{prev_.position, s.position};
            sw.material = s.op == ToolOp::kSubtract ? 0 : s.material;  // a cut exposes the workpiece's own material
            batch_.push_back(sw);
        }
        prev_ = s;
        have_prev_ = true;
    }
    if (!any) return false;
    if (!batch_.empty()) {
        const compute::BooleanStats b = backend_->apply(batch_);
        stats_.booleans += batch_.size();
        stats_.rays_changed += b.rays_changed;
        changed = b.rays_changed > 0;
    }
    // Haptics first: publish the changed surface before contouring, which only the renderer needs.
    // The window follows the god-object (ToolSample::surface_m), not the HIP, so a hand pushed deep into
    // material does not drag the window away from the proxy it constrains. (Widening the window to cover
    // the HIP too was tried: the coarser stride then hides thin walls, and the proxy ends inside material
    // far more often; tests/stress/test_stress_haptics.cpp measures both.)
    const Vec3 centre = is_finite(prev_.surface_m) ? prev_.surface_m : prev_.position;
    const double moved_cells = glm::length(centre - published_centre_m_) / model_.lattice.cell_m;
    if (changed || moved_cells > kRecentreCells) publish(centre);
    if (changed) {
        const auto t1 = std::chrono::steady_clock::now();
        if (gpu_contour_) {
            stats_.tiles_recontoured += gpu_contour_->update_dirty(model_.tiles);
            model_.clear_dirty();
        } else {
            stats_.tiles_recontoured += contourer_.update(model_);
        }
        ++stats_.steps;
        const auto t2 = std::chrono::steady_clock::now();
        stats_.boolean_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        stats_.contour_ms.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
        mesh_pending_ = mesh_out_ != nullptr;
    }
    return true;
}

void SculptThread::publish_mesh_to(TripleBuffer<MeshFrame>& out, double min_interval_s, MeshForm form) {
    if (thread_.joinable()) throw Error("SculptThread::publish_mesh_to: call it before start()");
    if (!std::isfinite(min_interval_s) || min_interval_s < 0.0)
        throw Error("SculptThread::publish_mesh_to: min_interval_s must be finite and >= 0, got " +
                    std::to_string(min_interval_s));
    mesh_out_ = &out;
    mesh_interval_s_ = min_interval_s;
    mesh_form_ = form;
    publish_mesh();
}

void SculptThread::publish_mesh() {
    const auto t0 = std::chrono::steady_clock::now();
    MeshFrame& slot = mesh_out_->back();
    slot.gpu = gpu_contour_ != nullptr;
    if (gpu_contour_) {  // the surface is in the GPU buffers: announce the change only
        slot.mesh = TriMesh{};
        slot.materials.clear();
        slot.tiles.clear();
        slot.tiled = true;
        slot.triangles = 0;  // the render thread counts the GPU contour's triangles itself
    } else if (mesh_form_ == MeshForm::kWhole) {
        slot.mesh = contourer_.mesh();
        slot.materials = contourer_.mesh_materials();
        slot.tiles.clear();
        slot.tiled = false;
        slot.triangles = slot.mesh.triangles.size();
    } else {
        tile_cache_.refresh(contourer_);
        // Reuse the shared copy of every tile whose (id, version) is unchanged: both lists are ordered by id.
        std::vector<std::shared_ptr<const compute::TileSurface>> next;
        next.reserve(tile_cache_.tiles().size());
        std::size_t k = 0, triangles = 0;
        for (const compute::TileSurface& t : tile_cache_.tiles()) {
            while (k < shared_tiles_.size() && shared_tiles_[k]->id < t.id) ++k;
            if (k < shared_tiles_.size() && shared_tiles_[k]->id == t.id && shared_tiles_[k]->version == t.version)
                next.push_back(shared_tiles_[k]);
            else
                next.push_back(std::make_shared<const compute::TileSurface>(t));
            triangles += t.mesh.triangles.size();
        }
        shared_tiles_ = std::move(next);
        slot.mesh = TriMesh{};
        slot.materials.clear();
        slot.tiles = shared_tiles_;
        slot.tiled = true;
        slot.triangles = triangles;
    }
    slot.sculpt_steps = stats_.steps;
    slot.published_s = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    slot.version = ++mesh_version_;
    mesh_out_->publish();
    mesh_pending_ = false;
    mesh_last_ = std::chrono::steady_clock::now();
    ++stats_.mesh_publishes;
    stats_.mesh_publish_ms.push_back(std::chrono::duration<double, std::milli>(mesh_last_ - t0).count());
}

void SculptThread::publish_mesh_if_due(bool force) {
    if (!mesh_pending_) return;
    const double since_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - mesh_last_).count();
    if (force || since_s >= mesh_interval_s_) publish_mesh();
}

void SculptThread::publish(const Vec3& centre_m) {
    const double extent_m = compute::tool_extent_m(tool_span_m_, have_prev_ ? tool_reach_m(prev_.tool) : tool_radius_m_);
    compute::extract_active_surface(model_, centre_m, extent_m, ++sequence_, surface_.back());
    surface_.publish();
    published_centre_m_ = centre_m;
    ++stats_.publishes;
}

}  // namespace tridex::app
