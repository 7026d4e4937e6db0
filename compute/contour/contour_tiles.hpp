// compute/contour/contour_tiles.hpp - the contoured surface as per-tile meshes for a renderer, rebuilt only
// where it changed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/tile_lod.hpp"
#include "core/aabb.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// One tile's part of the contoured surface, ready for a renderer: the triangles the tile owns, with the
/// vertices they use (its own and its neighbours'), world metres, CCW from outside.
struct TileSurface {
    std::uint64_t id = 0;       ///< tile index in the model's TileGrid (stable across updates)
    std::uint64_t version = 0;  ///< changes whenever this tile's mesh or a vertex it borrows from a neighbour changed
    Aabb bounds_m;              ///< box of mesh.positions, m
    TriMesh mesh;               ///< the tile's triangles (compact vertex list)
    /// Material id per mesh vertex (size = mesh.positions.size(); Contourer::mesh_materials' rule).
    std::vector<std::uint8_t> materials;
    /// Coarser levels of detail of mesh, finest first (build_tile_lod; empty unless the cache builds them).
    std::vector<TileLodLevel> lods;
};

/// Keeps TileSurfaces for every non-empty tile of a Contourer, rebuilding only tiles whose contour changed
/// (Contourer::tile_version, which also changes when only materials changed). Versions are unique per process, so one cache may follow a new Contourer
/// (e.g. after a reset): its tiles then all count as changed.
class TileSurfaceCache {
public:
    /// Rebuilds the tiles whose version changed since the last refresh (all on the first call) and drops
    /// tiles that became empty. Returns the number of tiles rebuilt. O(changed tiles' triangles) plus a
    /// scan of the tile versions. Throws tridex::Error as Contourer::tile_mesh (the cache is then unchanged).
    std::size_t refresh(const Contourer& contourer);
    /// The current tiles, ordered by id. refresh() may move them: references and pointers into it (e.g. to
    /// a tile's mesh) are valid until the next refresh().
    const std::vector<TileSurface>& tiles() const { return tiles_; }
    /// Total triangles over tiles().
    std::size_t triangle_count() const;

    /// From the next refresh() on, builds the levels of detail (TileSurface::lods, build_tile_lod) of every
    /// tile it rebuilds; call it before the first refresh() so that every tile has them. Large refreshes
    /// (kParallelLodTiles tiles or more, e.g. the first) spread the builds over the machine's cores.
    /// Throws tridex::Error when options.cell_m is not finite and > 0.
    void enable_lod(const TileLodOptions& options);
    /// True after enable_lod().
    bool lod_enabled() const { return lod_; }
    /// Tiles whose levels were built since construction, and the elapsed wall time of those builds, ms
    /// (a build spread over several cores counts its elapsed time once).
    std::size_t lod_tiles_built() const { return lod_tiles_built_; }
    double lod_build_ms() const { return lod_build_ms_; }
    /// Rebuilt tiles from which a refresh() builds the levels on every core.
    static constexpr std::size_t kParallelLodTiles = 64;

    /// true: refresh() builds no levels; the tiles it rebuilds wait (full mesh only, TileSurface::lods empty)
    /// until build_pending_lods() builds theirs, so that neither start-up nor a stroke's re-contour waits for
    /// them. false (the default): refresh() builds them at once.
    void defer_lods(bool on) { defer_ = on; }
    /// Tiles whose levels wait for build_pending_lods() (0 unless defer_lods(true) and enable_lod()).
    std::size_t lod_pending() const;
    /// Builds the levels of up to max_tiles waiting tiles (in tile order; on every core from kParallelLodTiles
    /// tiles), and gives each of them a new TileSurface::version (fresh_tile_version(): the published content
    /// changed) while refresh() keeps comparing with the Contourer's version. Returns the tiles built.
    /// Throws as build_tile_lod (those tiles then keep waiting).
    std::size_t build_pending_lods(std::size_t max_tiles);

private:
    void build_lods(const std::vector<TileSurface*>& tiles);
    std::vector<TileSurface> tiles_;
    std::vector<std::uint64_t> contour_versions_;  // per tiles_ entry: the Contourer's version it was built from
    std::vector<bool> pending_;                    // per tiles_ entry: levels wait for build_pending_lods()
    bool defer_ = false;
    bool lod_ = false;
    TileLodOptions lod_options_{};
    std::size_t lod_tiles_built_ = 0;
    double lod_build_ms_ = 0.0;
};

}  // namespace tridex::compute
