// app/input/surface_pick.cpp - cursor rays and ray-triangle picking on the contoured tiles.
#include "app/input/surface_pick.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tridex::app {

namespace {

// The slab test: true when the ray meets `box` (inflated by eps) before t_max.
bool meets_box(const Aabb& box, const Ray& ray, double t_max) {
    double t0 = 0.0, t1 = t_max;
    constexpr double kEps = 1e-6;  // m
    for (int a = 0; a < 3; ++a) {
        const double lo = box.lo[a] - kEps, hi = box.hi[a] + kEps;
        if (std::abs(ray.dir[a]) < 1e-300) {
            if (ray.origin_m[a] < lo || ray.origin_m[a] > hi) return false;
            continue;
        }
        double ta = (lo - ray.origin_m[a]) / ray.dir[a], tb = (hi - ray.origin_m[a]) / ray.dir[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        if (t0 > t1) return false;
    }
    return true;
}

// Nearest hit on `mesh` closer than best.distance_m (updated in place).
void pick_mesh(const TriMesh& mesh, const Ray& ray, std::optional<SurfaceHit>& best) {
    for (const auto& tri : mesh.triangles) {
        if (tri[0] >= mesh.positions.size() || tri[1] >= mesh.positions.size() || tri[2] >= mesh.positions.size())
            continue;
        const Vec3& a = mesh.positions[tri[0]];
        const Vec3 e1 = mesh.positions[tri[1]] - a, e2 = mesh.positions[tri[2]] - a;
        const Vec3 p = glm::cross(ray.dir, e2);
        const double det = glm::dot(e1, p);
        if (std::abs(det) < 1e-18) continue;
        const double inv = 1.0 / det;
        const Vec3 s = ray.origin_m - a;
        const double u = glm::dot(s, p) * inv;
        if (u < 0.0 || u > 1.0) continue;
        const Vec3 q = glm::cross(s, e1);
        const double v = glm::dot(ray.dir, q) * inv;
        if (v < 0.0 || u + v > 1.0) continue;
        const double t = glm::dot(e2, q) * inv;
        if (!(t > 0.0) || (best && t >= best->distance_m)) continue;
        Vec3 n = glm::cross(e1, e2);
        const double nl = glm::length(n);
        if (!(nl > 0.0)) continue;
        n /= nl;
        if (glm::dot(n, ray.dir) > 0.0) n = -n;
        best = SurfaceHit{ray.origin_m + t * ray.dir, n, t};
    }
}

}  // namespace

std::optional<Ray> cursor_ray(const renderer::Screen& screen, const Vec3& eye_m, double x_px, double y_px,
                              double width_px, double height_px) {
    if (!std::isfinite(x_px) || !std::isfinite(y_px) || !is_finite(eye_m) || !(width_px > 0.0) ||
        !(height_px > 0.0) || !std::isfinite(width_px) || !std::isfinite(height_px))
        return std::nullopt;
    const double u = x_px / width_px, v = 1.0 - y_px / height_px;  // 0..1 from the lower-left corner
    const Vec3 p = screen.lower_left + u * (screen.lower_right - screen.lower_left) +
                   v * (screen.upper_left - screen.lower_left);
    const Vec3 d = p - eye_m;
    const double n = glm::length(d);
    if (!(n > 0.0) || !std::isfinite(n)) return std::nullopt;
    return Ray{eye_m, d / n};
}

std::optional<SurfaceHit> pick_surface(const PickSurface& surface, const Ray& world_ray) {
    std::optional<SurfaceHit> best;
    if (!is_finite(world_ray.origin_m) || !is_finite(world_ray.dir)) return best;
    // The workpiece's tiles and mesh are in its model frame: the ray goes there, the hit comes back (a rigid pose
    // keeps the distance along the ray).
    const Pose& wp = surface.workpiece_pose;
    const Quat to_model = glm::conjugate(wp.orientation);
    const Ray ray{to_model * (world_ray.origin_m - wp.position), to_model * world_ray.dir};
    for (const auto& tile : surface.tiles) {
        if (!tile) continue;
        const double t_max = best ? best->distance_m : std::numeric_limits<double>::infinity();
        if (!meets_box(tile->bounds_m, ray, t_max)) continue;
        pick_mesh(tile->mesh, ray, best);
    }
    for (const auto& group : surface.groups) {
        if (!group || group->children_cover || group->lods.empty()) continue;
        const double t_max = best ? best->distance_m : std::numeric_limits<double>::infinity();
        if (!meets_box(group->bounds_m, ray, t_max)) continue;
        pick_mesh(group->lods.front().mesh, ray, best);
    }
    if (surface.whole) pick_mesh(*surface.whole, ray, best);
    if (best) {
        best->point_m = wp.apply(best->point_m);
        best->normal = wp.orientation * best->normal;
    }
    for (const PlacedMesh& placed : surface.placed) {
        if (!placed.mesh) continue;
        const Quat to_local = glm::conjugate(placed.pose.orientation);
        const Ray local{to_local * (world_ray.origin_m - placed.pose.position), to_local * world_ray.dir};
        const double t_max = best ? best->distance_m : std::numeric_limits<double>::infinity();
        if (!meets_box(placed.bounds_m, local, t_max)) continue;
        std::optional<SurfaceHit> hit = best;
        pick_mesh(*placed.mesh, local, hit);
        if (!hit || (best && !(hit->distance_m < best->distance_m))) continue;
        hit->point_m = placed.pose.apply(hit->point_m);  // a rigid pose keeps the distance along the ray
        hit->normal = placed.pose.orientation * hit->normal;
        best = hit;
    }
    return best;
}

}  // namespace tridex::app
