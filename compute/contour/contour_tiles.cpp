// compute/contour/contour_tiles.cpp - per-tile surface cache over a Contourer.
#include "compute/contour/contour_tiles.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <string>
#include <thread>
#include <utility>

#include "core/error.hpp"

namespace tridex::compute {

std::size_t TileSurfaceCache::refresh(const Contourer& contourer) {
    // First build the changed tiles aside, so an exception leaves the cache as it was.
    std::vector<TileSurface> rebuilt;
    std::size_t old = 0;  // walks tiles_ (sorted by id) alongside the tile indices
    const std::size_t count = contourer.tile_count();
    struct Step {
        bool fresh;
        std::size_t index;  // into rebuilt (fresh) or tiles_ (kept)
    };
    std::vector<Step> order;
    for (std::size_t t = 0; t < count; ++t) {
        while (old < tiles_.size() && tiles_[old].id < t) ++old;
        if (contourer.tile_triangle_count(t) == 0) continue;
        const std::uint64_t version = contourer.tile_version(t);
        if (old < tiles_.size() && tiles_[old].id == t && tiles_[old].version == version) {
            order.push_back({false, old});
            continue;
        }
        TileSurface s;
        s.id = t;
        s.version = version;
        s.mesh = contourer.tile_mesh(t, s.materials);
        s.bounds_m = s.mesh.bounds();
        order.push_back({true, rebuilt.size()});
        rebuilt.push_back(std::move(s));
    }
    if (lod_) build_lods(rebuilt);
    std::vector<TileSurface> next;
    next.reserve(order.size());
    for (const Step& st : order) next.push_back(std::move(st.fresh ? rebuilt[st.index] : tiles_[st.index]));
    tiles_ = std::move(next);
    return rebuilt.size();
}

void TileSurfaceCache::enable_lod(const TileLodOptions& options) {
    if (!std::isfinite(options.cell_m) || !(options.cell_m > 0.0))
        throw Error("TileSurfaceCache::enable_lod: cell_m must be finite and > 0, got " + std::to_string(options.cell_m));
    lod_options_ = options;
    lod_ = true;
}

void TileSurfaceCache::build_lods(std::vector<TileSurface>& rebuilt) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto build = [&](TileSurface& s) { s.lods = build_tile_lod(s.mesh, s.materials, lod_options_); };
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    if (rebuilt.size() < kParallelLodTiles || cores == 1) {
        for (TileSurface& s : rebuilt) build(s);
    } else {
        // Tiles handed out one at a time from a shared counter; the calling thread works too.
        std::atomic<std::size_t> next{0};
        std::exception_ptr failure;
        std::atomic<bool> failed{false};
        const auto work = [&] {
            for (std::size_t i; !failed.load() && (i = next.fetch_add(1)) < rebuilt.size();) {
                try {
                    build(rebuilt[i]);
                } catch (...) {
                    if (!failed.exchange(true)) failure = std::current_exception();
                }
            }
        };
        std::vector<std::thread> threads;
        for (unsigned c = 1; c < cores; ++c) threads.emplace_back(work);
        work();
        for (std::thread& t : threads) t.join();
        if (failure) std::rethrow_exception(failure);
    }
    lod_tiles_built_ += rebuilt.size();
    lod_build_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::size_t TileSurfaceCache::triangle_count() const {
    std::size_t n = 0;
    for (const TileSurface& s : tiles_) n += s.mesh.triangles.size();
    return n;
}

}  // namespace tridex::compute
