// compute/runtime/gpu_contour_share.cpp - the GPU contour shared by the sculpt and render threads.
#include "compute/runtime/gpu_contour_share.hpp"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <thread>
#include <vector>

namespace tridex::app {

GpuContourShare::GpuContourShare(const gpu::Context& context, const compute::GpuDexelSlabs& slabs,
                                 const compute::TriDexel& model, std::size_t initial_vertices,
                                 std::size_t initial_indices)
    : lattice_(model.lattice), tiles_(model.tiles.tiles),
      contourer_(std::make_unique<compute::GpuContourer>(context, slabs, model.lattice, initial_vertices,
                                                         initial_indices)) {}

std::size_t GpuContourShare::update_all() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::uint32_t> all(contourer_->tile_count());
    std::iota(all.begin(), all.end(), 0u);
    const std::size_t n = contourer_->update(all);
    if (n > 0) ++updates_;
    return n;
}

std::size_t GpuContourShare::update_dirty(const compute::TileGrid& grid) {
    const auto t0 = std::chrono::steady_clock::now();
    updates_waiting_.fetch_add(1, std::memory_order_acq_rel);
    std::lock_guard<std::mutex> lock(mutex_);
    updates_waiting_.fetch_sub(1, std::memory_order_acq_rel);
    const double wait_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    wait_total_ms_ += wait_ms;
    wait_max_ms_ = std::max(wait_max_ms_, wait_ms);
    const std::size_t n = contourer_->update_dirty(grid);
    if (n > 0) ++updates_;
    return n;
}

void GpuContourShare::rebuild_tiles() {
    list_.clear();
    triangles_ = 0;
    constexpr int k = compute::TileGrid::kTileCells;
    for (std::uint32_t id = 0; id < contourer_->tile_count(); ++id) {
        const std::uint32_t count = contourer_->tile_index_count(id);
        if (count == 0) continue;
        const int tx = static_cast<int>(id % tiles_[0]);
        const int ty = static_cast<int>((id / tiles_[0]) % tiles_[1]);
        const int tz = static_cast<int>(id / (static_cast<std::uint32_t>(tiles_[0]) * tiles_[1]));
        // A tile's vertices lie in its cells or, for vertices shared with a neighbour, one cell beyond.
        const Vec3 lo(tx * k - 1, ty * k - 1, tz * k - 1), hi((tx + 1) * k + 1, (ty + 1) * k + 1, (tz + 1) * k + 1);
        renderer::IndirectTile t;
        t.id = id;
        t.index_count = count;
        t.bounds_m = Aabb{lattice_.to_world(lo), lattice_.to_world(hi)};
        list_.push_back(t);
        triangles_ += count / 3;
    }
    listed_ = updates_;
}

std::unique_lock<std::mutex> GpuContourShare::lock_frame(renderer::IndirectWorkpiece& out) {
    while (updates_waiting_.load(std::memory_order_acquire) > 0) std::this_thread::yield();
    std::unique_lock<std::mutex> lock(mutex_);
    if (listed_ != updates_) rebuild_tiles();
    out.vertices = contourer_->vertex_buffer().handle();
    out.indices = contourer_->index_buffer().handle();
    out.commands = contourer_->draw_commands().handle();
    const float h = static_cast<float>(lattice_.cell_m);
    out.world_from_grid = glm::mat4(1.0f);
    out.world_from_grid[0][0] = h;
    out.world_from_grid[1][1] = h;
    out.world_from_grid[2][2] = h;
    out.world_from_grid[3] = glm::vec4(glm::vec3(lattice_.origin_m), 1.0f);
    out.tiles = list_;
    out.triangles = triangles_;
    return lock;
}

compute::GpuContourStats GpuContourShare::stats() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return contourer_->stats();
}

TriMesh GpuContourShare::download(std::vector<std::uint8_t>* materials) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return contourer_->download(materials);
}

std::uint64_t GpuContourShare::updates() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return updates_;
}

double GpuContourShare::lock_wait_ms_total() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return wait_total_ms_;
}

double GpuContourShare::lock_wait_ms_max() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return wait_max_ms_;
}

}  // namespace tridex::app
