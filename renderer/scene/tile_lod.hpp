// renderer/scene/tile_lod.hpp - which level of detail of a workpiece tile an eye draws: the coarsest whose
// geometric error projects to at most about a pixel.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/aabb.hpp"
#include "core/math.hpp"
#include "core/tri_mesh.hpp"
#include "renderer/camera/off_axis.hpp"

namespace tridex::renderer {

/// One coarser level of a tile's mesh (e.g. compute::TileLodLevel), as the renderer reads it.
struct TileMeshLevel {
    const TriMesh* mesh = nullptr;                       ///< world m; nullptr or empty: the level is not used
    const std::vector<std::uint8_t>* materials = nullptr;  ///< per vertex, or nullptr (material 0)
    /// Per vertex unit normals to shade with (e.g. the full mesh's at the same vertices), or nullptr: the
    /// level's own area-weighted normals.
    const std::vector<Vec3>* normals = nullptr;
    double error_m = 0.0;  ///< largest distance between this level's surface and the full mesh's, m (>= 0)
    /// A group level contoured from the model read at a coarser stride (compute::TileLodLevel::own_triangles): its
    /// leading triangles that are the group's own, before the ring and skirt that close it against neighbours drawn
    /// at other levels. 0: always drawn whole.
    std::size_t own_triangles = 0;
    /// With own_triangles: the neighbouring groups (TileGroup::neighbours slots) that must draw their own triangles of
    /// the same depth for this level to be drawn without its ring and skirt (compute::TileLodLevel::joins).
    std::uint32_t joins = 0;
};

/// What an eye needs to project lengths: the off-axis eye of off_axis_view() and the screen's pixel density.
struct LodEye {
    Mat4 view{1.0};            ///< world -> eye space (axes: screen right, up, normal; the eye looks along -z)
    double screen_distance_m = 0.0;  ///< eye to screen plane, m (> 0)
    double pixels_per_screen_m = 0.0;  ///< image pixels per metre on the screen: max(width / screen width, height / screen height)
};

/// The LodEye of an eye at eye_m looking through `screen` into a width_px x height_px image.
/// Throws tridex::Error as off_axis_view(), and when width_px or height_px < 1.
LodEye lod_eye(const Screen& screen, const Vec3& eye_m, int width_px, int height_px);

/// Upper bound of the image pixels that a displacement of one metre anywhere in `box_m` moves its projection
/// by (the spectral norm of the projection's Jacobian, (D / d) * sqrt(1 + r^2 / d^2) for screen distance D,
/// depth d >= the box's smallest depth and lateral offset r <= its largest, times pixels per screen metre).
/// +infinity when the box reaches the eye's plane (depth <= 0); 0 for an empty box. Throws tridex::Error when
/// a non-empty box is not finite.
double pixels_per_metre(const LodEye& eye, const Aabb& box_m);

/// The level to draw: the largest k in 1..levels.size() whose error_m * px_per_m <= max_px (a level with a
/// null or empty mesh is never chosen), else 0 (the full mesh). levels are finest first.
std::size_t choose_level(std::span<const TileMeshLevel> levels, double px_per_m, double max_px);

}  // namespace tridex::renderer
