// compute/contour/contour_tile.hpp - manifold dual contouring of one tile of cells into a cached piece of mesh.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "compute/contour/contour_qef.hpp"
#include "compute/contour/contour_sample.hpp"
#include "compute/contour/contour_table.hpp"
#include "compute/model/tridexel.hpp"

namespace tridex::compute::contour {

/// Names a mesh vertex independently of the tile that stores it, so tiles can be redone one by one and
/// stitched by key. key = node_linear_index(n) * 32 + slot, where n is the vertex's "anchor" node:
///  - slot 0..3:   component `slot` of the cell with min node n (a dual vertex);
///  - slot 4..6:   crossing point of the lattice edge from n along axis slot-4 (only for split edges);
///  - slot 8..19:  8 + 4*f + corner: segment vertex of a split face perpendicular to f with min node n,
///                 for the segment around the face's inside corner `corner` (face_corners order).
/// Every vertex, edge polygon and face belongs to the tile of the cell with the same index as its
/// anchor node; it depends only on nodes n - 1 .. n + 1 on each axis and the edges between them (the
/// cells n - 1 and n), through the corner fill (contour::kCornerFillReach) on the edges of those cells'
/// face-adjacent cells (nodes n - 2 .. n + 2), and, through the crossing normals (contour_qef.hpp), on the
/// rays one node beside those edges and their interval ends up to kNormalWindow cells along them;
/// TriDexel::mark_dirty covers that (cells within four cells of a change).
using VertexKey = std::uint64_t;

/// Anchor node of a key and the tile owning it.
struct KeyCodec {
    std::array<int, 3> nodes{};  ///< lattice nodes per axis (cells + 1)
    std::array<int, 3> tiles{};  ///< tiles per axis

    /// Key of slot `slot` at node n.
    VertexKey key(const Node& n, int slot) const {
        return ((static_cast<std::uint64_t>(n[2]) * nodes[1] + n[1]) * nodes[0] + n[0]) * 32u + static_cast<std::uint64_t>(slot);
    }
    /// Anchor node of key k (the inverse of key(), slot dropped).
    Node anchor(VertexKey k) const;
    /// Linear index (TileGrid::index order) of the tile that owns key k.
    std::size_t owner_tile(VertexKey k) const;
};

/// The cached mesh piece of one tile, in grid units.
struct TileMesh {
    std::vector<VertexKey> keys;   ///< vertices this tile owns, sorted ascending
    static constexpr std::size_t kNotOwned = static_cast<std::size_t>(-1);
    /// Index in `keys` of vertex `key` (a binary search), or kNotOwned when this tile does not own it.
    std::size_t find(VertexKey key) const {
        const auto it = std::lower_bound(keys.begin(), keys.end(), key);
        return it == keys.end() || *it != key ? kNotOwned : static_cast<std::size_t>(it - keys.begin());
    }
    std::vector<Vec3> grid;        ///< their positions, grid units, parallel to keys
    /// Their material ids, parallel to keys (rule: see TileContourer, "vertex materials").
    std::vector<std::uint8_t> materials;
    /// Triangles, CCW from outside. A reference r < kForeign is the local vertex r (index into keys);
    /// r >= kForeign is the vertex foreign[r - kForeign], owned by a neighbour tile and found by key at
    /// assembly (neighbours may be redone in between, so their indices are not kept).
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<VertexKey> foreign;  ///< sorted keys of vertices owned by other tiles
    static constexpr std::uint32_t kForeign = 0x80000000u;
    /// Per triangle, the tile-local index of the cell that emitted it (local_cell()); ascending, the order
    /// in which the cells are visited. A partial run keeps the triangles of the cells it does not redo.
    std::vector<std::uint16_t> triangle_cells;
    /// Per owned vertex (parallel to keys), how the QEF placed it: kQef* bits (0 for edge and face vertices).
    std::vector<std::uint8_t> qef;
    static constexpr std::uint8_t kQefNormals = 1, kQefTruncated = 2, kQefRejected = 4, kQefClamped = 8;
    /// Tile-local cells with an owned fallback edge, and with a split face, one entry each, ascending.
    std::vector<std::uint16_t> fallback_cells, split_face_cells;
    /// Tile-local index of the cell at offsets (i, j, k) from the tile's first cell, each in 0..kTileCells-1.
    static std::uint16_t local_cell(int i, int j, int k) {
        return static_cast<std::uint16_t>(i + TileGrid::kTileCells * (j + TileGrid::kTileCells * k));
    }
    /// Non-uniform cells processed by the run that made it (uniform cells are skipped in bulk).
    std::size_t cells_visited = 0;
    std::size_t fallbacks = 0;     ///< owned sign-change edges whose ray had no end on the edge
    std::size_t split_faces = 0;   ///< owned faces split to keep the surface 2-manifold
    // Owned vertices by the QEF branch that placed them (QefOutcome; a vertex may count in several):
    std::size_t qef_vertices = 0;  ///< placed by a QEF of at least one crossing normal (else: the mass point)
    std::size_t qef_truncated = 0; ///< ... with at least one eigen-direction dropped (a face or an edge, not a corner)
    std::size_t qef_rejected = 0;  ///< ... with no finite minimiser (non-finite normals: the mass point instead)
    std::size_t qef_clamped = 0;   ///< ... whose free minimiser lay outside the cell (minimised on its boundary)
};

/// Contours single tiles; keeps scratch buffers between calls (not thread-safe, one per thread).
///
/// Method (manifold dual contouring on the shared tri-dexel lattice):
///  - node occupancy from the X rays (OccupancyBlock); cells whose 8 corners agree are skipped by
///    32-bit row masks, so the work per tile is proportional to its surface cells;
///  - one dual vertex per surface component of a cell (cell_cases()), placed by the QEF of that
///    component's edge crossings and their normals estimated from neighbouring rays (qef_vertex(),
///    crossing_normal() in contour_qef.hpp: sharp edges and corners are kept; when only some of them have
///    one, the others take the normal of the plane fitted through all of them, fit_normal()), relative to
///    their mass point (mean) and minimised over the cell. Normals from a crease's flat side join ordinary
///    ones only when consistent with them (acute angles, vertex within kCreaseResidual of their planes);
///    a component whose normals include a nearly opposite pair (kOpposedNormalCos: the two walls of a sheet
///    thinner than the cell) keeps only the normals of the wall with more of them and fits no plane; a
///    concave crease vertex far behind its crossings and cut off by a face-adjacent cell's tangent plane
///    takes that plane too (the corner fill, kCornerFillReach: a third surface filling the crease's corner); a
///    component none of whose crossings has a normal borrows, per crossing, the nearest tangent plane's normal from
///    the face-adjacent cells' crossings and keeps one wall of an obtuse pair (kBorrowReach: an air gap narrower
///    than the cell), and so do the crossings without one of a component whose normals all came from one-sided
///    slopes when a borrowed normal contradicts its own (kBorrowWrongCos: the crest of a fin thinner than the cell);
///  - every sign-change lattice edge emits the quad of the components containing it in its 4 cells,
///    oriented from the edge's inside end to its outside end (outward normals), split along the shorter
///    diagonal;
///  - repair of the one case where that is not 2-manifold: a face whose two segments belong to one
///    component in BOTH cells beside it (a tunnel thinner than a cell) would make two quads' shared
///    edges coincide. Such a face gets one vertex per segment (the QEF of the segment's two crossings
///    with their normals' in-face parts, kept in the rectangle spanned by the segment's inside corner and
///    its crossings; their mean without normals; of two nearly opposite normals, a sheet's facing walls, only
///    the first's), and
///    each edge polygon touching it becomes a fan around the edge's crossing point. Each dual vertex's
///    triangle fan stays a single cycle, so the mesh is a closed 2-manifold for any occupancy.
///
/// Vertex materials: every vertex takes the material of the interval end (EdgeCrossing::material) of the
/// edge crossing nearest to it (Euclidean, grid units) among the crossings that generated it: a dual
/// vertex among its component's crossings in its cell, a split-face vertex among its segment's two
/// crossings, an edge-crossing vertex its own crossing. Tie-break on exactly equal distances: the larger
/// material id (paint wins over clay 0 at a seam; it also makes the rule independent of visiting order).
/// Computed while the vertex is placed, from the same crossings (no extra pass over the model).
class TileContourer {
public:
    /// Recomputes `out` for tile t (tile coordinates) of `model`. Reads only rays through nodes t*16 - 5
    /// .. t*16 + 20 of each axis (GpuContourer::fill_scratch_rays lists what reads them). Does not touch the model's dirty flags.
    ///
    /// Partial run: with `previous` (this tile's last result, not `out` itself) and `cells` (global cell
    /// indices within the tile, TileGrid::kPartial), only the non-uniform cells in `cells` are redone and the
    /// mesh items of every other cell (the vertices anchored at it, the triangles it emitted) are copied from
    /// `previous`. The caller guarantees that no cell outside `cells` can have changed since `previous`
    /// (TriDexel::mark_dirty's reach); the result is then the whole run's, bit for bit, in the same order.
    /// When the kept items refer to a vertex the run no longer has (the box missed a change), the tile is
    /// redone whole instead.
    void run(const TriDexel& model, const std::array<int, 3>& t, TileMesh& out, const TileMesh* previous = nullptr,
             const CellBox* cells = nullptr);

private:
    static constexpr std::uint8_t kQefNormals = TileMesh::kQefNormals, kQefTruncated = TileMesh::kQefTruncated,
                                  kQefRejected = TileMesh::kQefRejected, kQefClamped = TileMesh::kQefClamped;
    struct CellVertices {
        std::uint32_t stamp = 0;  // equals stamp_ when pos holds this run's positions
        std::array<Vec3, kMaxComponents> pos{};
        std::array<std::uint8_t, kMaxComponents> material{};
        // How each vertex was placed: QefOutcome packed into kQef* bits (one byte keeps the cache small).
        std::array<std::uint8_t, kMaxComponents> qef{};
    };
    struct Vertex {
        VertexKey key;
        Vec3 pos;
        std::uint8_t material;
        std::uint8_t qef;  // kQef* bits (dual vertices), else 0
    };
    /// A sign-change edge's crossing and normal, computed once per run for the up to 4 cells sharing it.
    struct EdgeSample {
        std::uint32_t stamp = 0;  // equals stamp_ when this run computed it
        bool has_normal = false;
        bool crease = false;     // the normal came from the flat side of a crease (contour::crossing_normal)
        bool one_sided = false;  // a slope other than 0 came from one side alone (contour::crossing_normal)
        EdgeCrossing crossing;
        Vec3 normal{0.0};
    };
    static constexpr int kCacheSpan = TileGrid::kTileCells + 1;  // cells t*16 - 1 .. t*16 + 15
    static constexpr int kEdgeSpan = kCacheSpan + 1;              // their edges' start nodes per axis

    // The crossing and normal of the edge from node `start` along axis a, cached for this run (contour_cell.cpp).
    const EdgeSample& edge_sample(const Node& start, int a, bool start_inside);
    // The dual vertices of `cell` (one per component: position, material, QEF outcome), cached for this run; see the
    // method above (contour_cell.cpp).
    const CellVertices& cell_vertices(const Node& cell);
    const Vec3& vertex(const Node& cell, int component) { return cell_vertices(cell).pos[component]; }
    void emit_edge(const Node& n, int a);
    void emit_split_face(const Node& n, int f);
    // Keeps the mesh items of `previous` whose cell lies outside `cells` (a partial run), merged in cell order
    // with those of this run's cells.
    void keep_outside(const TileMesh& previous, const CellBox& cells, const Node& c0);
    // Turns verts_, tri_keys_ and tri_cells_ into `out` (sorted vertices, resolved references, counters);
    // `previous`: a partial run's previous piece, whose vertices kept triangles refer to. Returns false (a
    // partial run only) when a kept triangle's vertex is gone or one of this tile's vertices is missing.
    bool assemble(const Node& c0, const TileMesh* previous, TileMesh& out);
    // Marks a tri_keys_ entry that is the index of a vertex of the previous piece, not a key (keys stay far below).
    static constexpr VertexKey kPreviousVertex = VertexKey{1} << 63;
    bool face_split(const Node& lower, int f) const;

    const TriDexel* model_ = nullptr;
    KeyCodec codec_;
    OccupancyBlock occ_;
    Node cache_lo_{};
    std::vector<CellVertices> cache_;
    std::vector<EdgeSample> edges_;  // 3 per node of the kEdgeSpan^3 block at cache_lo_
    std::uint32_t stamp_ = 0;
    std::vector<Vertex> verts_;
    std::vector<std::array<VertexKey, 3>> tri_keys_;
    std::vector<std::uint16_t> tri_cells_;  // parallel to tri_keys_: the emitting cell (TileMesh::local_cell)
    std::vector<std::uint16_t> fallback_cells_, split_face_cells_;
    std::uint16_t cell_ = 0;            // the cell being visited (TileMesh::local_cell)
    std::vector<std::uint32_t> remap_;  // previous piece's vertex -> index in the new piece
};

}  // namespace tridex::compute::contour
