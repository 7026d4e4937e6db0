// compute/contour/deferred_contour.cpp - tiles whose full-resolution contour waits while a stroke is open.
#include "compute/contour/deferred_contour.hpp"

#include <algorithm>
#include <string>

#include "compute/contour/tile_group_box.hpp"
#include "core/error.hpp"

namespace tridex::compute {

DeferredContour::DeferredContour(const std::array<int, 3>& tiles) : dims_(tiles) {
    std::size_t n = 1;
    for (const int k : tiles) n *= static_cast<std::size_t>(std::max(0, k));
    deferred_.assign(n, 0);
    touched_.assign(n, 0);
    near_.assign(n, 0);
    changes_ = TileChangeLog(TileChangeLog::entries_for(n));
}

template <typename F>
void DeferredContour::for_neighbourhood(std::size_t t, F&& f) const {
    const auto nx = static_cast<std::size_t>(dims_[0]), ny = static_cast<std::size_t>(dims_[1]);
    const int cx = static_cast<int>(t % nx), cy = static_cast<int>(t / nx % ny), cz = static_cast<int>(t / (nx * ny));
    for (int z = std::max(0, cz - 1); z <= std::min(dims_[2] - 1, cz + 1); ++z)
        for (int y = std::max(0, cy - 1); y <= std::min(dims_[1] - 1, cy + 1); ++y)
            for (int x = std::max(0, cx - 1); x <= std::min(dims_[0] - 1, cx + 1); ++x)
                f(static_cast<std::size_t>(x) + nx * (static_cast<std::size_t>(y) + ny * static_cast<std::size_t>(z)));
}

std::vector<std::uint64_t> DeferredContour::defer(TriDexel& model) {
    if (model.tiles.tiles != dims_)
        throw Error("DeferredContour::defer: the model's tile grid differs from the one this deferral was made for");
    std::vector<std::uint64_t> changed;
    for (std::size_t t = 0; t < deferred_.size(); ++t) {
        if (!model.tiles.dirty[t]) continue;
        changed.push_back(t);
        touched_[t] = 1;
        if (deferred_[t]) continue;
        deferred_[t] = 1;
        ++count_;
        order_.push_back(t);
        const std::uint64_t stamp = fresh_tile_version();
        for_neighbourhood(t, [&](std::size_t n) {
            changes_.add(stamp, n);  // hidden() of it and of the touched tiles around it (recorded first)
            ++near_[n];
        });
    }
    model.clear_dirty();
    return changed;
}

void DeferredContour::release(TriDexel& model, std::size_t t) {
    model.tiles.dirty[t] = TileGrid::kWhole;
    deferred_[t] = 0;
    ++released_;
    if (--count_ == 0) order_.clear();
    const std::uint64_t stamp = fresh_tile_version();
    for_neighbourhood(t, [&](std::size_t n) {
        changes_.add(stamp, n);
        if (--near_[n] == 0 && touched_[n] && !deferred_[n]) {
            touched_[n] = 0;
            visible_.push_back(n);
        }
    });
}

std::size_t DeferredContour::release_box(TriDexel& model, std::array<int, 3> lo, std::array<int, 3> hi) {
    std::size_t marked = 0;
    for (int z = std::max(0, lo[2]); z <= std::min(dims_[2] - 1, hi[2]); ++z)
        for (int y = std::max(0, lo[1]); y <= std::min(dims_[1] - 1, hi[1]); ++y)
            for (int x = std::max(0, lo[0]); x <= std::min(dims_[0] - 1, hi[0]); ++x) {
                const std::size_t t = model.tiles.index(x, y, z);
                if (!deferred_[t]) continue;
                release(model, t);
                ++marked;
            }
    return marked;
}

std::size_t DeferredContour::take_dirty(TriDexel& model, std::vector<std::uint64_t>* released) {
    if (count_ == 0 || model.tiles.tiles != dims_) return 0;
    std::vector<std::size_t> dirty;
    for (std::size_t t = 0; t < deferred_.size(); ++t)
        if (model.tiles.dirty[t] && near_[t] > 0) dirty.push_back(t);  // a deferred tile among it and its neighbours
    std::size_t marked = 0;
    for (const std::size_t t : dirty)
        for_neighbourhood(t, [&](std::size_t n) {
            if (!deferred_[n]) return;
            release(model, n);
            ++marked;
            if (released) released->push_back(n);
        });
    return marked;
}

std::size_t DeferredContour::contour_oldest(TriDexel& model, Contourer& contourer, std::size_t max_tiles) {
    return contour_oldest_where(model, contourer, max_tiles, [](std::uint64_t) { return true; });
}

std::size_t DeferredContour::contour_oldest_where(TriDexel& model, Contourer& contourer, std::size_t max_tiles,
                                                  const std::function<bool(std::uint64_t)>& wanted) {
    std::size_t marked = 0;
    std::vector<std::uint64_t> kept;  // deferred tiles passed over, oldest first
    while (marked < max_tiles && !order_.empty()) {
        const std::uint64_t t = order_.front();
        order_.pop_front();
        if (!deferred_[t]) continue;  // contoured since (take_dirty, contour_group)
        if (!wanted(t)) {
            kept.push_back(t);
            continue;
        }
        release(model, t);
        ++marked;
    }
    order_.insert(order_.begin(), kept.begin(), kept.end());
    if (marked > 0) contourer.update(model);
    return marked;
}

std::size_t DeferredContour::contour_group(TriDexel& model, Contourer& contourer, int depth,
                                           const std::array<int, 3>& coords) {
    std::array<int, 3> lo{}, hi{};
    if (count_ == 0 || !group_tiles_grown(dims_, depth, coords, lo, hi)) return 0;
    const std::size_t marked = release_box(model, lo, hi);
    if (marked > 0) contourer.update(model);
    return marked;
}

std::size_t DeferredContour::contour_all(TriDexel& model, Contourer& contourer) {
    return contour_oldest(model, contourer, deferred_.size());
}

std::vector<std::uint64_t> DeferredContour::take_visible() {
    std::vector<std::uint64_t> out = std::move(visible_);
    visible_.clear();
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace tridex::compute
