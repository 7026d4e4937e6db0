// compute/contour/tile_group_lod.hpp - levels of detail over a group of neighbouring tiles: their meshes merged
// and simplified with only the group's outer border kept.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "compute/contour/tile_lod.hpp"
#include "core/math.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// One piece of a group's surface: a tile's full mesh or a level of a tile or of a smaller group.
struct LodPart {
    const TriMesh* mesh = nullptr;             ///< world m, CCW from outside; nullptr or empty: skipped
    std::span<const std::uint8_t> materials;   ///< per mesh vertex, or empty (material 0)
    std::span<const Vec3> normals;             ///< per mesh vertex unit normals, or empty (the mesh's own)
    double error_m = 0.0;                      ///< distance bound between this piece and the surface it stands for, m
};

/// The pieces welded into one mesh: a vertex on a piece's open border becomes one with the vertex at the
/// bit-identical position on an earlier piece's border (neighbouring tiles share their border vertices exactly);
/// vertices inside a piece, and two of one piece at one position, stay distinct. A welded vertex keeps the first
/// piece's material and the normalised sum of the pieces' normals. `materials` and `normals` get one entry per merged vertex (materials all 0 when no piece has
/// any). Throws tridex::Error when a piece's materials or normals have the wrong size or an index is out of
/// range. O(V log V) for V vertices over the pieces.
TriMesh merge_lod_parts(std::span<const LodPart> parts, std::vector<std::uint8_t>& materials, std::vector<Vec3>& normals);

/// The levels of detail of a group of tiles: merge_lod_parts of `parts`, then build_lod_levels with base error
/// = the largest piece error, so each level's error_m bounds its distance to the full-resolution surface of
/// the whole group. The merged mesh's open border (the group's outer border: edges whose other triangle lies in
/// a tile outside the group) is kept exactly as the pieces have it, so the group's levels meet any neighbour
/// drawn at any of its levels edge to edge; the borders between the group's tiles are simplified away.
/// Empty when the merged mesh is too small, does not simplify or its border is not manifold. Throws as
/// merge_lod_parts and build_lod_levels, and when a part's error_m is negative or not finite.
std::vector<TileLodLevel> build_group_lod(std::span<const LodPart> parts, const TileLodOptions& options);

}  // namespace tridex::compute
