// compute/contour/contour_dual.hpp - tri-dexel model -> closed 2-manifold triangle mesh, redoing dirty tiles only.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "compute/contour/contour_tile.hpp"
#include "compute/contour/tile_change_log.hpp"
#include "compute/model/tridexel.hpp"
#include "core/progress.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// Next value of the process-wide tile version counter that Contourer::tile_version() draws from (never 0,
/// never repeated): for a tile whose published content changes without a re-contour (e.g. its levels of detail
/// arrive later, TileSurfaceCache::build_pending_lods). Thread-safe.
std::uint64_t fresh_tile_version();

/// Counters of a Contourer (all for the current mesh unless marked "last update").
struct ContourStats {
    std::size_t tiles = 0;               ///< tiles of the lattice
    std::size_t tiles_recontoured = 0;   ///< tiles redone by the last update()
    std::size_t tiles_partial = 0;       ///< ... of which only their changed cells were (TileGrid::kPartial)
    std::size_t cells_visited = 0;       ///< non-uniform cells processed by the last update()
    std::size_t vertices = 0;            ///< mesh vertices
    std::size_t triangles = 0;           ///< mesh triangles
    std::size_t fallbacks = 0;           ///< sign-change edges whose own ray had no interval end on them
    std::size_t split_faces = 0;         ///< faces split to keep the mesh 2-manifold (sub-cell tunnels)
    // Mesh vertices by how the QEF placed them (contour_qef.hpp QefOutcome; vertices - qef_vertices -
    // qef_rejected had no crossing normal and sit at their mass point):
    std::size_t qef_vertices = 0;        ///< placed by a QEF of at least one crossing normal
    std::size_t qef_truncated = 0;       ///< ... with an eigen-direction dropped (on a face or an edge)
    std::size_t qef_rejected = 0;        ///< no finite minimiser (non-finite normals): the mass point instead
    std::size_t qef_clamped = 0;         ///< free minimiser outside the cell: the QEF minimised on the cell's boundary
};

/// Contours a tri-dexel model into a closed, consistently oriented (outward) 2-manifold triangle mesh in
/// world metres, keeping per-tile results so only dirty tiles are redone.
///
/// Method: manifold dual contouring on the model's shared lattice (details in contour_tile.hpp and
/// contour_table.hpp). Node occupancy comes from the X rays (enter <= x < exit; lattice-boundary nodes
/// are outside, so the mesh is closed); each sign-change edge's crossing comes from its own ray (Peng et
/// al., tri-dexel model: every lattice edge lies on one ray). One vertex per surface component of a cell,
/// placed by the QEF of its crossings with normals estimated from neighbouring rays (sharp edges and
/// corners kept; contour_qef.hpp); one quad per sign-change edge, split along the shorter diagonal. For
/// any occupancy the result has no boundary, non-manifold or misoriented edge and no pinched vertex.
/// Cost: proportional to the surface cells of the dirty tiles (uniform cells are skipped by bit masks)
/// plus (kTileCells + 5)^2 ray reads per ray set and dirty tile (the crossing normals read the rays beside
/// the tile's own).
class Contourer {
public:
    /// Binds to the model's lattice and tile grid (sizes only; no data read yet).
    explicit Contourer(const TriDexel& model);
    /// Dirty tiles from which update() uses every core (the task pool: no thread is started per update).
    static constexpr std::size_t kParallelTiles = 2;

    /// Re-contours every dirty tile of `model`, then clears the model's dirty flags. Returns the number of
    /// tiles re-contoured. Large updates (kParallelTiles dirty tiles or more, e.g. an undo) are split over the
    /// machine's cores as one task per tile on the persistent task pool (compute/parallel/task_pool.hpp; each
    /// tile's result does not depend on the split). The first call must contour every dirty tile (scan conversion marks all tiles
    /// holding surface dirty). A tile flagged TileGrid::kPartial that this Contourer has contoured before
    /// redoes only the cells of its box and keeps the rest of its piece (the same piece, bit for bit, as a
    /// whole re-contour); any other dirty tile is redone whole. Throws tridex::Error when `model` is not on the lattice this Contourer was
    /// built for, or its ray sets do not match that lattice (the model is then left unchanged). `progress`
    /// (core/progress.hpp) hears the fraction of the dirty tiles done, on the calling thread, up to kProgressSlices
    /// times (compute/parallel/task_pool.hpp; the result does not depend on it).
    std::size_t update(TriDexel& model, const ProgressFn& progress = {});

    /// The whole current mesh (assembled from all tiles), world metres, CCW from outside. O(T log V).
    /// Throws tridex::Error when tiles reference vertices a stale neighbour tile lacks (the model was
    /// changed somewhere mark_dirty() did not cover, or the first update() did not see all tiles dirty).
    TriMesh mesh() const;
    /// Per-vertex material ids of mesh(): one per mesh().positions entry, same order (the vertices are the
    /// same, bit for bit). Rule: each vertex takes the material of the interval end of its nearest
    /// generating edge crossing (contour::TileContourer, "vertex materials"); 0 = the workpiece's own.
    /// O(V); no model access, never throws.
    std::vector<std::uint8_t> mesh_materials() const;

    /// Counters of the current mesh and of the last update().
    ContourStats stats() const;

    // ---- Per-tile access (for renderers that draw and re-upload the surface tile by tile). ----

    /// Number of tiles (= the model's TileGrid::count(); index order tx + tiles_x * (ty + tiles_y * tz)).
    std::size_t tile_count() const { return tile_meshes_.size(); }
    /// Tiles along x, y and z (the model's TileGrid::tiles).
    std::array<int, 3> tile_dims() const { return tiles_; }
    /// Triangles tile `tile` owns (0 = the tile holds no surface). Throws tridex::Error when tile >= tile_count().
    std::size_t tile_triangle_count(std::size_t tile) const;
    /// Content version of tile `tile`'s surface: changes after an update() exactly when the triangles the
    /// tile owns or the positions or materials of its own vertices changed, or a vertex they use that a
    /// neighbour tile owns moved, changed material or vanished (so a paint-only stroke, which moves no
    /// vertex, still gives the painted tiles new versions), or a triangle around a vertex it uses was added,
    /// removed or reshaped in any tile (the vertex's surface normal, tile_mesh(tile, materials, normals), changed; a
    /// few such tiles get a new version although the normal came out the same); otherwise
    /// unchanged (a dirty tile whose re-contour gave the same piece keeps its version). Values come from one
    /// process-wide counter, so versions of different Contourers never coincide; 0 = never contoured.
    /// Throws tridex::Error when tile >= tile_count().
    std::uint64_t tile_version(std::size_t tile) const;
    /// Appends the tiles whose version changed after `mark` (a fresh_tile_version() value) to `out`, unsorted, with
    /// repeats, and returns true; false when this Contourer cannot tell (a mark from before it was made, or older than
    /// its record keeps: TileChangeLog). O(log n + answer).
    bool tiles_changed_since(std::uint64_t mark, std::vector<std::uint64_t>& out) const {
        return changes_.since(mark, out);
    }
    /// Identifies this Contourer's record of changes among the process's (TileMeshSource::change_view).
    std::uint64_t change_id() const { return changes_.id(); }
    /// The triangles tile `tile` owns as a compact mesh, world metres, CCW from outside: its own vertices
    /// that those triangles use, then the borrowed ones (owned by neighbour tiles), each once. The union of
    /// all tiles' triangles is mesh()'s triangles (same positions, bit for bit). O(tile triangles x log).
    /// Throws tridex::Error when tile >= tile_count(), or as mesh() when a borrowed vertex is missing.
    TriMesh tile_mesh(std::size_t tile) const;
    /// As tile_mesh(tile), also filling `materials` with one material id per returned vertex (same order;
    /// equal to mesh_materials() of the same vertices). Throws as tile_mesh() (`materials` then unspecified).
    TriMesh tile_mesh(std::size_t tile, std::vector<std::uint8_t>& materials) const;
    /// As tile_mesh(tile, materials), also filling `normals` with one unit normal per returned vertex: the
    /// area-weighted normal of the whole surface at that vertex (the triangles of every tile that use it, the
    /// neighbour tiles' included), so that neighbouring tiles shade a vertex they share alike: core
    /// vertex_normals(mesh()) at the same vertex, bit for bit (the same triangles summed in the same order). A
    /// vertex whose triangles have no area gets (0, 0, 0).
    /// Reads the tile's 26 neighbours' triangles near it. Throws as tile_mesh().
    TriMesh tile_mesh(std::size_t tile, std::vector<std::uint8_t>& materials, std::vector<Vec3>& normals) const;

private:
    /// tile_mesh's assembly; with `keys`, also the vertex key of each returned vertex.
    TriMesh assemble_tile(std::size_t tile, std::vector<std::uint8_t>& materials,
                          std::vector<contour::VertexKey>* keys) const;
    /// The whole surface's area-weighted unit normal at each vertex of tile `tile`'s assembled `mesh` (`keys`: their
    /// keys, parallel to mesh.positions), summed over the triangles of the tile and its neighbours in ascending tile
    /// order (contour_tile_normals.cpp).
    void surface_normals(std::size_t tile, const TriMesh& mesh, const std::vector<contour::VertexKey>& keys,
                         std::vector<Vec3>& normals) const;
    /// Tiles outside `changed` (`slot`: position in `changed` + 1 per tile, 0 if not changed) whose vertex normals
    /// the update may have changed: those using a vertex of a triangle it added, removed or reshaped, in a changed
    /// tile or in another tile through a vertex that moved. Appended to `bump` (the tiles already in it are kept).
    void normal_sharers(const std::vector<std::pair<std::size_t, contour::TileMesh>>& changed,
                        const std::vector<std::uint32_t>& slot, std::vector<std::size_t>& bump) const;
    void check_model(const TriDexel& model) const;
    void check_tile(std::size_t tile) const;
    /// Index of vertex `key` in the piece of its owner tile (tile, index); throws as mesh() when that tile
    /// lacks it.
    std::pair<std::size_t, std::size_t> owned_vertex(contour::VertexKey key) const;
    /// Gives a new version to each changed tile and to each tile borrowing a vertex of a changed tile
    /// that moved or vanished (`changed`: tile index and its piece before the update).
    void bump_versions(const std::vector<std::pair<std::size_t, contour::TileMesh>>& changed);

    Lattice lattice_;
    std::array<int, 3> tiles_{};
    contour::KeyCodec codec_;
    std::vector<contour::TileMesh> tile_meshes_;
    std::vector<contour::TileContourer> workers_;  // scratch per task-pool slot, made on first use
    std::size_t last_tiles_ = 0;
    std::size_t last_partial_tiles_ = 0;
    std::size_t last_cells_ = 0;
    std::vector<std::uint8_t> contoured_;  // per tile: 1 once an update() has contoured it (its piece is current)
    std::vector<std::uint64_t> versions_;  // per tile, see tile_version()
    // Per tile, its piece's triangle count: a cache's refresh reads many tiles' (every tile's when it cannot tell the
    // changed ones), and a TileMesh per tile is far larger than a cache line.
    std::vector<std::uint32_t> triangle_counts_;
    TileChangeLog changes_;  // every version given, with its tile
};

}  // namespace tridex::compute
