// compute/contour/coarse_levels.hpp - levels of detail of tile groups contoured straight from the dexels: a
// depth-d group's level is the contour of the model read at every 2^d-th ray (coarse_lattice.hpp), with a ring
// and a skirt that close the cracks against neighbours drawn at other levels.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/tile_lod.hpp"
#include "compute/model/tridexel.hpp"

namespace tridex::compute {

/// How the coarse levels are made.
struct CoarseLevelOptions {
    int max_depth = 3;  ///< groups of depth min_depth..max_depth (2^d tiles along each axis) get a level, at stride 2^d
    /// Groups shallower than this keep their simplified levels (TileSurfaceCache). Depth 1 reads the model at stride 2:
    /// that model and its contour hold a quarter of the model's rays and triangles, so 2 trades those levels for memory.
    int min_depth = 1;
    /// The level's error (TileLodLevel::error_m) in cells of its own coarse lattice: an estimate of the distance to
    /// the full-resolution surface, not a bound (a feature thinner than a coarse cell between its rays is missed
    /// whole). `tridex bench --coarse` measures the two-sided distance.
    double error_coarse_cells = 1.0;
    /// Depth of the skirt hung from the level's open border, in cells of its coarse lattice (> 0).
    double skirt_coarse_cells = 1.0;
};

/// The coarse levels of every group of tiles of one model, kept up to date as the model changes.
///
/// A depth-d group covers 2^d x 2^d x 2^d tiles of kTileCells cells, which is exactly one tile of the model read at
/// stride s = 2^d (coarse_model): its level is that coarse tile's contour (manifold dual contouring on the coarse
/// lattice, with its own sharp-feature placement), plus a ring: the triangles of the neighbouring coarse tiles
/// whose centroid lies within one coarse cell of the group's box, so that the level reaches past the group's border
/// by more than the width by which a neighbour's border, at any level, can fall short of it. A skirt then hangs
/// from the ring's open border, inward along the vertex normals by skirt_coarse_cells coarse cells, drawn from
/// both sides, so no gap shows between the level and a neighbour within that distance of it. Overlaps between a
/// level and its neighbours lie within the level's error of the surface. (Chunked levels with skirts follow
/// T. Ulrich, "Rendering massive terrains using chunked level of detail control", SIGGRAPH 2002 course notes.)
/// Not thread-safe: one thread updates and reads it.
class CoarseGroupLevels {
public:
    /// Reads `fine` at strides 2^first_depth ... 2^max_depth and contours each coarse model whole (on the task pool);
    /// first_depth 0 means min_depth (every depth). The finer depths wait for build_depth(). Throws tridex::Error when
    /// options are out of range (1 <= min_depth <= max_depth <= 6, cells > 0 and finite) or first_depth is neither 0
    /// nor in min_depth..max_depth.
    CoarseGroupLevels(const TriDexel& fine, const CoarseLevelOptions& options, int first_depth = 0);
    ~CoarseGroupLevels();
    CoarseGroupLevels(const CoarseGroupLevels&) = delete;
    CoarseGroupLevels& operator=(const CoarseGroupLevels&) = delete;

    /// After `fine` changed: re-reads the coarse rays through the tiles `changed_tiles` (fine tile indices, e.g.
    /// the tiles whose contour version changed) and the kDirtyReachCells cells around them, each ray once and on the
    /// task pool, marks dirty the coarse cells around the interval ends that moved, and re-contours those, at the
    /// depths from_depth..max_depth() that are built (0: from min_depth()). Returns the coarse tiles re-contoured over
    /// those depths. Calling it again for the same change re-reads the rays and finds nothing to re-contour.
    std::size_t update(const TriDexel& fine, std::span<const std::uint64_t> changed_tiles, int from_depth = 0);

    /// Depths with levels (min_depth()..max_depth()).
    int min_depth() const { return options_.min_depth; }
    int max_depth() const { return options_.max_depth; }
    /// True when depth d's coarse model is built (by the constructor or build_depth()); false outside the depths.
    bool has_depth(int depth) const;
    /// Reads `fine` at stride 2^depth (nothing when that depth is built already). Unlike the constructor, it does not
    /// contour that coarse model: read_around() contours the coarse tiles the groups it is given need, the first time
    /// they are needed, so that reading a depth costs only its rays (depth 1 contoured whole would cost about a quarter
    /// of the model's whole contour) and each level's contour comes with it. The contour is the same, tile for tile,
    /// as the constructor's. Throws tridex::Error for a depth outside min_depth()..max_depth().
    void build_depth(const TriDexel& fine, int depth);
    /// The level of the depth-d group at `coords` (group coordinates, as TileGroupSurface::coords): its mesh in
    /// world m with the ring and the skirt, per-vertex materials and normals, error_m = error_coarse_cells coarse
    /// cells. The group's own triangles come first (TileLodLevel::own_triangles, with the neighbours they join in
    /// TileLodLevel::joins), then the ring's and the skirt's: a renderer may draw only the own ones where every
    /// joined neighbour draws its own level of this depth. An empty mesh where the coarse contour has no surface near
    /// the group. Throws tridex::Error for a depth
    /// outside min_depth()..max_depth() or not built yet (has_depth), coords outside that depth's group grid, or a
    /// group of a depth read by build_depth() whose tiles read_around() has not contoured yet.
    TileLodLevel level(int depth, const std::array<int, 3>& coords) const;
    /// Reads the meshes of the coarse tiles the levels of `groups` (depth, coords) take (each group's and the 26 around
    /// it) where their contour changed since they were last read, first contouring those of a depth read by
    /// build_depth() that were never contoured (and the tiles next to them, whose vertices they share), so that
    /// level() of those groups then only reads (several threads may call it at once until the next update(),
    /// read_around() or forget_reads()). Throws as level() for a depth, and as Contourer::update.
    void read_around(std::span<const std::pair<int, std::array<int, 3>>> groups);
    /// True when read_around() of the depth-d group at `coords` would contour nothing, only read: its depth was
    /// contoured whole, or the coarse tiles its level takes were contoured before. Throws as level() for a depth or
    /// coords.
    bool contoured_around(int depth, const std::array<int, 3>& coords) const;
    /// Frees the tile meshes read so far (level() reads what it needs again).
    void forget_reads();

private:
    struct Depth;
    const Depth& at(int depth) const;
    CoarseLevelOptions options_;
    std::vector<std::unique_ptr<Depth>> levels_;  // [depth - min_depth]; null until built
};

/// Adds a skirt to `mesh` (with per-vertex `materials` and `normals`, same size as its positions): for every open
/// border edge (used by one triangle), a quad hanging from it along minus each end's normal by depth_m, in both
/// windings. The new vertices copy their top vertex's material and normal. Returns the border edges skirted.
/// Throws tridex::Error when the per-vertex arrays' sizes differ from the positions'.
std::size_t add_skirt(TriMesh& mesh, std::vector<std::uint8_t>& materials, std::vector<Vec3>& normals, double depth_m);

}  // namespace tridex::compute
