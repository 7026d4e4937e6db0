// app/input/surface_pick.hpp - a ray from the eye through a cursor pixel, and where it first meets the contoured surface.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "compute/contour/contour_tiles.hpp"
#include "core/aabb.hpp"
#include "core/math.hpp"
#include "core/pose.hpp"
#include "core/tri_mesh.hpp"
#include "renderer/camera/off_axis.hpp"

namespace tridex::app {

/// A ray: origin (m) and unit direction, in the frame of the screen and eye it was made from.
struct Ray {
    Vec3 origin_m{0.0};
    Vec3 dir{0.0, 0.0, -1.0};
};

/// The ray from `eye_m` (m; the cyclopean eye for a stereo view) through the point of `screen` (m) under the
/// cursor at (x_px, y_px) (pixels from the top-left of an image of width_px x height_px covering the whole
/// screen). nullopt for a non-finite cursor or eye, a non-positive image size, or an eye on the screen point.
std::optional<Ray> cursor_ray(const renderer::Screen& screen, const Vec3& eye_m, double x_px, double y_px,
                              double width_px, double height_px);

/// Where a ray meets a surface.
struct SurfaceHit {
    Vec3 point_m{0.0};   ///< the hit point, m
    Vec3 normal{0.0};    ///< unit normal of the triangle hit, turned to face the ray's origin
    double distance_m = 0.0;  ///< from the ray's origin, m
};

/// A mesh placed in the scene by a rigid pose (a reference object): its triangles in its own frame, m.
struct PlacedMesh {
    const TriMesh* mesh = nullptr;  ///< own frame, m; must outlive every PickSurface holding it; null = skipped
    Pose pose;                      ///< own frame -> world
    Aabb bounds_m;                  ///< the mesh's bounds in its own frame (culls the ray first)
};

/// The surface a pick runs against: the published tiles (each with its bounds, culled first) or a whole mesh.
struct PickSurface {
    std::vector<std::shared_ptr<const compute::TileSurface>> tiles;  ///< the tiles (immutable once published)
    std::shared_ptr<const TriMesh> whole;                              ///< or one mesh (may be null)
    /// Groups of tiles (MeshFrame::groups): those whose tiles cannot stand in yet (a coarse-first start-up,
    /// TileGroupSurface::children_cover false) are picked on their finest level, as they are drawn.
    std::vector<std::shared_ptr<const compute::TileGroupSurface>> groups;
    /// Meshes placed by a pose (the scene's reference objects), picked like the workpiece.
    std::vector<PlacedMesh> placed;
    /// The workpiece's pose: `tiles`, `groups` and `whole` are in its model frame, placed into the world by it.
    Pose workpiece_pose{};
};

/// The nearest hit of `ray` (world) on `surface` (Moller-Trumbore on the triangles of the tiles whose bounds it meets,
/// and of the placed meshes, the ray taken into each one's frame, the workpiece's too); the hit is in the world, or nullopt when it misses. Degenerate triangles are skipped; never throws.
std::optional<SurfaceHit> pick_surface(const PickSurface& surface, const Ray& ray);

}  // namespace tridex::app
