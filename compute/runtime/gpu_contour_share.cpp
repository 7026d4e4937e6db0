// compute/runtime/gpu_contour_share.cpp - the GPU contour shared by the sculpt and render threads.
#include "compute/runtime/gpu_contour_share.hpp"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <thread>
#include <unordered_map>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "core/error.hpp"

namespace tridex::app {
namespace {

// The GPU contour's tiles as read back by GpuContourShare::redo, as a TileMeshSource.
template <typename ReadBack>
class ReadBackTiles final : public compute::TileMeshSource {
public:
    ReadBackTiles(const std::vector<std::uint64_t>& versions, const std::vector<std::uint32_t>& triangles,
                  const std::unordered_map<std::uint32_t, ReadBack>& read, const std::array<int, 3>& dims)
        : versions_(versions), triangles_(triangles), read_(read), dims_(dims) {}
    std::size_t tile_count() const override { return versions_.size(); }
    std::array<int, 3> tile_dims() const override { return dims_; }
    std::size_t tile_triangle_count(std::size_t t) const override { return triangles_.at(t); }
    std::uint64_t tile_version(std::size_t t) const override { return versions_.at(t); }
    TriMesh tile_mesh(std::size_t t, std::vector<std::uint8_t>& materials, std::vector<Vec3>& normals) const override {
        const auto r = read_.find(static_cast<std::uint32_t>(t));
        if (r == read_.end()) throw Error("GPU contouring: tile " + std::to_string(t) + " changed but was not read back");
        materials = r->second.materials;
        normals.clear();  // the GPU contour is drawn with its facets' normals
        return r->second.mesh;
    }

private:
    const std::vector<std::uint64_t>& versions_;
    const std::vector<std::uint32_t>& triangles_;
    const std::unordered_map<std::uint32_t, ReadBack>& read_;
    std::array<int, 3> dims_;
};

}  // namespace

GpuContourShare::GpuContourShare(const gpu::Context& context, const compute::GpuDexelSlabs& slabs,
                                 const compute::TriDexel& model, std::size_t initial_vertices,
                                 std::size_t initial_indices)
    : lattice_(model.lattice),
      tiles_(model.tiles.tiles),
      contourer_(
          std::make_unique<compute::GpuContourer>(context, slabs, model.lattice, initial_vertices, initial_indices)),
      versions_(contourer_->tile_count(), 0) {}

std::size_t GpuContourShare::redo(const std::vector<std::uint32_t>& tiles) {
    const std::size_t n = contourer_->update(tiles);
    for (const std::uint32_t t : tiles) versions_[t] = compute::fresh_tile_version();
    if (n > 0) ++updates_;
    // Copy the redone tiles out now, while the buffers are locked, so refresh_tiles never waits for a frame.
    if (read_back_.load(std::memory_order_acquire)) stash(tiles);
    return n;
}

void GpuContourShare::stash(const std::vector<std::uint32_t>& tiles) {
    std::lock_guard<std::mutex> lock(stash_mutex_);
    if (stash_versions_.empty()) {
        stash_versions_.assign(versions_.size(), 0);
        stash_triangles_.assign(versions_.size(), 0);
    }
    std::vector<compute::GpuContourVertex> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<std::uint32_t> remap;
    for (const std::uint32_t t : tiles) {
        stash_versions_[t] = versions_[t];
        stash_triangles_[t] = contourer_->tile_index_count(t) / 3;
        if (stash_triangles_[t] == 0) {
            stash_tiles_.erase(t);
            continue;
        }
        contourer_->download_tile(t, vertices, triangles);
        // Compact: only the vertices the tile's triangles use, in first-use order; each float grid position as
        // drawn, in world m (double): (p - origin) / cell gives the float back.
        remap.assign(vertices.size(), ~0u);
        ReadBack& read = stash_tiles_[t];
        TriMesh& m = read.mesh;
        std::vector<std::uint8_t>& materials = read.materials;
        m = TriMesh{};
        materials.clear();
        m.triangles.reserve(triangles.size());
        for (const auto& tri : triangles) {
            std::array<std::uint32_t, 3> out{};
            for (int k = 0; k < 3; ++k) {
                std::uint32_t& to = remap[tri[k]];
                if (to == ~0u) {
                    const compute::GpuContourVertex& v = vertices[tri[k]];
                    to = static_cast<std::uint32_t>(m.positions.size());
                    m.positions.push_back(lattice_.origin_m + Vec3(v.grid[0], v.grid[1], v.grid[2]) * lattice_.cell_m);
                    materials.push_back(static_cast<std::uint8_t>(std::min<std::uint32_t>(v.material, 255u)));
                }
                out[k] = to;
            }
            m.triangles.push_back(out);
        }
    }
}

void GpuContourShare::read_back_tiles() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (read_back_.load()) return;
    read_back_.store(true, std::memory_order_release);
    if (updates_ == 0) return;  // the first update copies every tile
    std::vector<std::uint32_t> all(contourer_->tile_count());
    std::iota(all.begin(), all.end(), 0u);
    stash(all);
}

std::size_t GpuContourShare::update_all() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::uint32_t> all(contourer_->tile_count());
    std::iota(all.begin(), all.end(), 0u);
    return redo(all);
}

std::size_t GpuContourShare::update_dirty(const compute::TileGrid& grid) {
    const auto t0 = std::chrono::steady_clock::now();
    updates_waiting_.fetch_add(1, std::memory_order_acq_rel);
    std::lock_guard<std::mutex> lock(mutex_);
    updates_waiting_.fetch_sub(1, std::memory_order_acq_rel);
    const double wait_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    wait_total_ms_ += wait_ms;
    wait_max_ms_ = std::max(wait_max_ms_, wait_ms);
    if (grid.count() != versions_.size())
        throw Error("GPU contouring: the tile grid has " + std::to_string(grid.count()) + " tiles, the contourer " +
                    std::to_string(versions_.size()));
    return redo(grid.dirty_tiles());
}

std::uint64_t GpuContourShare::tile_version(std::size_t tile) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (tile >= versions_.size())
        throw Error("GPU contouring: tile " + std::to_string(tile) + " out of range (the lattice has " +
                    std::to_string(versions_.size()) + " tiles)");
    return versions_[tile];
}

std::size_t GpuContourShare::refresh_tiles(compute::TileSurfaceCache& cache) {
    if (!read_back_.load(std::memory_order_acquire))
        throw Error("GpuContourShare::refresh_tiles: call read_back_tiles() first");
    std::lock_guard<std::mutex> stash(stash_mutex_);
    if (stash_versions_.empty()) return 0;  // nothing contoured yet
    const std::size_t n = cache.refresh(ReadBackTiles<ReadBack>(stash_versions_, stash_triangles_, stash_tiles_, tiles_));
    // Every copy is now in the cache (the tiles it read) or stale (a tile read back and redone before this).
    stash_tiles_.clear();
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
        t.version = versions_[id];
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
    out.grid_origin_m = lattice_.origin_m;
    out.cell_m = lattice_.cell_m;
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
