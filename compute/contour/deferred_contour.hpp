// compute/contour/deferred_contour.hpp - tiles whose full-resolution contour waits while a stroke is open: the frames
// draw the stroke from the coarse group levels meanwhile (docs/design/lod.md, "Strokes drawn coarse").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <utility>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/tile_change_log.hpp"
#include "compute/contour/tile_mesh_source.hpp"
#include "compute/model/tridexel.hpp"

namespace tridex::compute {

/// The tiles a stroke changed whose full-resolution contour has not been redone yet.
///
/// While a stroke is open, the sculpt thread hands the model's dirty tiles to defer() instead of contouring them; the
/// Contourer keeps their old contour, which Source hides, and the coarse group levels over them (rebuilt with each
/// step) stand in. The tiles are contoured later, a few at a time (contour_oldest, contour_group), or with the next
/// change contoured at once (take_dirty). A tile's mesh borrows vertices from its 26 neighbours: a neighbour the
/// change did not mark dirty keeps its mesh bit for bit (TriDexel::kDirtyReachCells covers every cell whose contour
/// reads a changed end), so it stays drawn; a deferred tile contoured before a deferred neighbour stays hidden until
/// that neighbour is contoured too. Each tile is contoured from the model as it is then, by the same
/// Contourer::update as a change contoured at once, so once none waits the contour equals, bit for bit, the one a
/// contour after every step gives. Not thread-safe: its owner (the sculpt thread, a render rank's replica) calls it.
class DeferredContour {
public:
    /// Deferred tiles contoured at a time after a stroke, oldest first (a batch of the sculpt thread's or a render
    /// rank's slice).
    static constexpr std::size_t kTilesPerBatch = 32;

    /// Nothing deferred, for a model with `tiles` tiles along x, y and z (TileGrid::tiles).
    explicit DeferredContour(const std::array<int, 3>& tiles);

    /// Takes every tile `model` marks dirty into the deferred set and clears the model's dirty flags. Returns those
    /// tiles, ascending (each changed, whether or not it was deferred already): they are hidden from now on.
    /// Throws tridex::Error when the model's tile count is not this one's.
    std::vector<std::uint64_t> defer(TriDexel& model);
    /// Before the caller contours a change at once (Contourer::update): every deferred tile among the dirty ones or
    /// next to one is marked dirty whole (its old contour may differ anywhere) and leaves the set, so that no tile the
    /// change contours borrows a vertex from an old contour. Returns how many; `released` (may be null) receives
    /// their ids too, in no particular order.
    std::size_t take_dirty(TriDexel& model, std::vector<std::uint64_t>* released = nullptr);
    /// Contours the deferred tiles, oldest deferral first, until `max_tiles` are marked. Returns how many were
    /// contoured (0 when none waits). Throws as Contourer::update.
    std::size_t contour_oldest(TriDexel& model, Contourer& contourer, std::size_t max_tiles);
    /// Contours the deferred tiles of the depth-`depth` tile group at group coordinates `coords`
    /// (TileGroupSurface::coords: 2^depth tiles along each axis) and those within one tile of it, so that the group's
    /// tiles can all be drawn after it. Returns how many: 0 when none waits there, the depth is outside 1..6 or the
    /// group lies outside the grid. Throws as Contourer::update.
    std::size_t contour_group(TriDexel& model, Contourer& contourer, int depth, const std::array<int, 3>& coords);
    /// As contour_oldest, among the deferred tiles `wanted` says true for (a view may see them); the others keep their
    /// place in the order. Returns how many were contoured. Throws as Contourer::update.
    std::size_t contour_oldest_where(TriDexel& model, Contourer& contourer, std::size_t max_tiles,
                                     const std::function<bool(std::uint64_t)>& wanted);
    /// Contours every deferred tile. Returns how many. Throws as Contourer::update.
    std::size_t contour_all(TriDexel& model, Contourer& contourer);

    /// True while tile t's contour waits (false for out-of-range t).
    bool deferred(std::size_t t) const { return t < deferred_.size() && deferred_[t] != 0; }
    /// True while tile t may not be drawn: its contour waits, or it was deferred and a neighbour's still waits.
    bool hidden(std::size_t t) const {
        return t < deferred_.size() && (deferred_[t] != 0 || (touched_[t] != 0 && near_[t] > 0));
    }
    /// Tiles whose contour waits.
    std::size_t count() const { return count_; }
    /// The tiles hidden since defer() that may be drawn again since the last call, ascending, each once.
    std::vector<std::uint64_t> take_visible();
    /// Deferred tiles released for contouring since the last call (by contour_*, take_dirty).
    std::size_t take_released() { return std::exchange(released_, 0); }

    /// A tile source seen through the deferral: a hidden tile has no triangles. Valid while both live.
    class Source final : public TileMeshSource {
    public:
        Source(const TileMeshSource& base, const DeferredContour& d) : base_(base), d_(d) {}
        std::size_t tile_count() const override { return base_.tile_count(); }
        std::array<int, 3> tile_dims() const override { return base_.tile_dims(); }
        std::size_t tile_triangle_count(std::size_t t) const override {
            return d_.hidden(t) ? 0 : base_.tile_triangle_count(t);
        }
        std::uint64_t tile_version(std::size_t t) const override { return base_.tile_version(t); }
        TriMesh tile_mesh(std::size_t t, std::vector<std::uint8_t>& materials,
                          std::vector<Vec3>& normals) const override {
            return base_.tile_mesh(t, materials, normals);
        }
        bool changed_since(std::uint64_t mark, std::vector<std::uint64_t>& out) const override {
            return base_.changed_since(mark, out) && d_.changes_.since(mark, out);
        }
        std::uint64_t change_view() const override {
            return combine_change_views(base_.change_view(), d_.changes_.id());
        }

    private:
        const TileMeshSource& base_;
        const DeferredContour& d_;
    };

private:
    // Marks deferred tile t dirty whole and takes it out of the set; its neighbours may become visible.
    void release(TriDexel& model, std::size_t t);
    // Marks the deferred tiles of the box [lo, hi] (tile coordinates, clamped to the grid) dirty whole and takes them
    // out of the set; returns how many.
    std::size_t release_box(TriDexel& model, std::array<int, 3> lo, std::array<int, 3> hi);
    // Calls f(n) for tile t and each of its 26 neighbours inside the grid.
    template <typename F>
    void for_neighbourhood(std::size_t t, F&& f) const;
    std::array<int, 3> dims_{};
    std::vector<std::uint8_t> deferred_;  // per tile: 1 while its contour waits
    std::vector<std::uint8_t> touched_;   // per tile: 1 from its deferral until it is visible again
    std::vector<std::uint8_t> near_;      // per tile: deferred tiles among it and its 26 neighbours
    std::deque<std::uint64_t> order_;     // deferrals, oldest first (tiles released since are skipped)
    std::vector<std::uint64_t> visible_;  // tiles visible again since the last take_visible()
    TileChangeLog changes_;               // each tile whose hidden() may have changed, with the stamp it may have
    std::size_t count_ = 0;
    std::size_t released_ = 0;
};

}  // namespace tridex::compute
