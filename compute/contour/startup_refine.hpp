// compute/contour/startup_refine.hpp - start-up's full-resolution contour, one region of tiles at a time, after a
// first mesh made of coarse group levels (docs/design/lod.md, "Coarse first at start-up").
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/tile_change_log.hpp"
#include "compute/contour/tile_mesh_source.hpp"
#include "compute/model/tridexel.hpp"
#include "core/math.hpp"

namespace tridex::compute {

class DeferredContour;

/// Contours a freshly loaded model at full resolution a region at a time, so that a first mesh can be published
/// before any tile is contoured (from coarse group levels, TileSurfaceCache::use_coarse_groups) and the tiles then
/// replace it region by region.
///
/// A region is a depth-`region_depth` group of tiles (2^region_depth tiles along each axis). A tile's mesh borrows
/// vertices from its 26 neighbours (Contourer::tile_mesh), so a tile can be published once it and every neighbour
/// have been contoured: refine_next() contours a region's tiles and those within one tile of it, so every tile of
/// the region is publishable after it. Regions go nearest a given point first (the tool). Each tile is contoured
/// once, by the same Contourer::update() as a whole contour, so the finished contour equals, bit for bit, the one a
/// single update() of the loaded model gives. Not thread-safe: the sculpt thread owns it.
class StartupRefiner {
public:
    /// Takes the tiles `model` marks dirty (scan conversion marks every tile holding surface, loading every tile) that
    /// hold an interval end of some ray or lie next to one as the tiles to contour (a tile without one holds no
    /// surface), and clears the model's dirty flags (the Contourer must not have contoured the model yet).
    /// O(rays x intervals + tiles).
    /// Regions nearer near_m (world m) come first. Throws tridex::Error when region_depth is outside 1..6.
    StartupRefiner(TriDexel& model, int region_depth, const Vec3& near_m);

    /// True once every tile has been contoured.
    bool done() const { return pending_count_ == 0; }
    /// Tiles still waiting for their first contour.
    std::size_t pending() const { return pending_count_; }
    /// The tiles still waiting for their first contour, ascending.
    std::vector<std::uint64_t> pending_tiles() const;
    /// True when tile t and its 26 neighbours are all contoured (or never need to be): its mesh can be read.
    bool publishable(std::size_t t) const { return t < near_pending_.size() && near_pending_[t] == 0; }
    /// The tiles that became publishable since the last call, ascending (each reported once).
    std::vector<std::uint64_t> take_newly_publishable();

    /// Contours the pending tiles of the next region that has any, and those within one tile of it, with
    /// `contourer` (bound to `model`, whose dirty flags must be clear). Returns the tiles contoured (0 when done).
    /// Throws as Contourer::update.
    std::size_t refine_next(TriDexel& model, Contourer& contourer);
    /// Contours the pending tiles of the depth-`depth` tile group at group coordinates `coords` (TileGroupSurface::
    /// coords: 2^depth tiles along each axis) and those within one tile of it, so that every tile of the group is
    /// publishable after it. Returns the tiles contoured: 0 when none was pending, the depth is outside 1..6 or the
    /// group lies outside the grid. Throws as Contourer::update.
    std::size_t refine_group(TriDexel& model, Contourer& contourer, int depth, const std::array<int, 3>& coords);
    /// Of `tiles` (e.g. a change's dirty tiles), those still waiting for their first contour, ascending.
    std::vector<std::uint64_t> pending_among(const std::vector<std::uint64_t>& tiles) const;
    /// Before a change's re-contour: marks dirty (kWhole unless already dirty) every pending tile of the depth-1
    /// groups (2x2x2 tiles) of `tiles` and of their 26 neighbours, and within one tile of those groups, so that all
    /// those groups' tiles can be published after it and draw the change at full resolution; counts them as
    /// contoured (the caller's Contourer::update() follows at once). Returns how many were marked.
    std::size_t contour_with_change(TriDexel& model, const std::vector<std::uint64_t>& tiles);
    /// Contours every pending tile. Returns how many. Throws as Contourer::update.
    std::size_t finish(TriDexel& model, Contourer& contourer);
    /// From now on, before each contour it makes, the deferred tiles of `deferral` within one tile of the tiles it
    /// contours are contoured with them (DeferredContour::take_dirty): a stroke's tiles it would contour anyway are
    /// contoured once, not again by the deferral, and its region can be drawn without waiting for them. `deferral`
    /// must outlive this refiner; nullptr: none.
    void contour_beside(DeferredContour* deferral) { beside_ = deferral; }

    /// `contourer` seen through the refiner: a tile that is not publishable has no triangles. Valid while both live.
    class Source final : public TileMeshSource {
    public:
        Source(const Contourer& c, const StartupRefiner& r) : c_(c), r_(r) {}
        std::size_t tile_count() const override { return c_.tile_count(); }
        std::array<int, 3> tile_dims() const override { return c_.tile_dims(); }
        std::size_t tile_triangle_count(std::size_t t) const override {
            return r_.publishable(t) ? c_.tile_triangle_count(t) : 0;
        }
        std::uint64_t tile_version(std::size_t t) const override { return c_.tile_version(t); }
        TriMesh tile_mesh(std::size_t t, std::vector<std::uint8_t>& materials,
                          std::vector<Vec3>& normals) const override {
            return c_.tile_mesh(t, materials, normals);
        }
        bool changed_since(std::uint64_t mark, std::vector<std::uint64_t>& out) const override {
            return c_.tiles_changed_since(mark, out) && r_.changes_.since(mark, out);
        }
        std::uint64_t change_view() const override { return combine_change_views(c_.change_id(), r_.changes_.id()); }

    private:
        const Contourer& c_;
        const StartupRefiner& r_;
    };

private:
    void contour(TriDexel& model, Contourer& contourer);  // Contourer::update after contour_beside's deferral
    DeferredContour* beside_ = nullptr;
    std::array<int, 3> coords(std::size_t t) const;
    std::vector<std::uint8_t> near_surface(const TriDexel& model) const;  // per tile: may hold surface
    std::size_t index(int x, int y, int z) const;
    // Marks dirty (kWhole unless already dirty) the pending tiles of region r and within one tile of it, and counts
    // them contoured. Returns how many.
    std::size_t mark_region(TriDexel& model, std::size_t region);
    // Marks the pending tiles of the box [lo, hi] (tile coordinates, clamped to the grid) for contouring and takes
    // them out of the pending set; returns how many.
    std::size_t mark_box(TriDexel& model, std::array<int, 3> lo, std::array<int, 3> hi);
    void contoured(std::size_t t);  // t leaves the pending set
    // Calls f(n) for the index n of tile c and of each of its 26 neighbours inside the grid.
    template <typename F>
    void for_neighbourhood(const std::array<int, 3>& c, F&& f) const {
        for (int z = std::max(0, c[2] - 1); z <= std::min(dims_[2] - 1, c[2] + 1); ++z)
            for (int y = std::max(0, c[1] - 1); y <= std::min(dims_[1] - 1, c[1] + 1); ++y)
                for (int x = std::max(0, c[0] - 1); x <= std::min(dims_[0] - 1, c[0] + 1); ++x) f(index(x, y, z));
    }
    std::array<int, 3> dims_{};
    std::array<int, 3> region_dims_{};
    int depth_ = 3;
    std::vector<std::uint8_t> pending_;      // per tile: 1 while waiting for its first contour
    std::vector<std::uint8_t> near_pending_; // per tile: pending tiles among it and its 26 neighbours
    std::vector<std::uint8_t> reported_;     // per tile: 1 once take_newly_publishable() returned it
    std::vector<std::uint64_t> fresh_;       // tiles that became publishable since the last take
    TileChangeLog changes_;                  // each tile that became publishable, with the stamp it did
    std::vector<std::size_t> order_;         // regions holding pending tiles at the start, nearest first
    std::size_t next_ = 0;                   // the first of order_ not yet refined
    std::size_t pending_count_ = 0;
};

}  // namespace tridex::compute
