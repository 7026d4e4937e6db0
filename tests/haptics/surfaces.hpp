// tests/haptics/surfaces.hpp - hand-built ActiveSurface snapshots for the haptics tests.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "core/active_surface.hpp"

namespace tridex::test {

/// Solid intervals [enter, exit] of one ray, grid units.
using Intervals = std::vector<std::pair<float, float>>;

/// An empty snapshot with sequence 1, lattice origin `origin_m` (m), cell `cell_m` (m), 64 nodes per axis.
inline std::unique_ptr<ActiveSurface> make_surface(double cell_m, const Vec3& origin_m = Vec3(0.0)) {
    auto s = std::make_unique<ActiveSurface>();
    s->sequence = 1;
    s->cell_m = cell_m;
    s->origin_m = origin_m;
    s->nodes = {64, 64, 64};
    return s;
}

/// Fills the whole kWindow x kWindow window of ray set `axis`, first ray at lattice (u0, v0), every
/// `stride`-th lattice ray (ActiveSurface::lattice_ray), with the intervals rays(u, v) returns for
/// lattice indices (u, v).
inline void fill_set(ActiveSurface& s, int axis, int u0, int v0, const std::function<Intervals(int, int)>& rays,
                     int stride = 1) {
    ActiveSurface::Window& w = s.sets[axis];
    w.u0 = u0;
    w.v0 = v0;
    w.stride = stride;
    w.nu = ActiveSurface::kWindow;
    w.nv = ActiveSurface::kWindow;
    w.count.fill(0);
    for (int iv = 0; iv < w.nv; ++iv)
        for (int iu = 0; iu < w.nu; ++iu) {
            const std::array<int, 2> uv = s.lattice_ray(axis, iu, iv);
            const Intervals in = rays(uv[0], uv[1]);
            const int idx = iu + ActiveSurface::kWindow * iv;
            w.count[idx] = static_cast<std::uint8_t>(in.size());
            for (std::size_t n = 0; n < in.size(); ++n) {
                w.depth[(idx * ActiveSurface::kMaxIntervals + n) * 2] = in[n].first;
                w.depth[(idx * ActiveSurface::kMaxIntervals + n) * 2 + 1] = in[n].second;
            }
        }
}

/// Snapshot of the half-space z < c_cells (grid units) seen by the Z rays only: every Z ray holds
/// [0, c_cells]. Cell `cell_m`, origin 0, window over lattice x, y in [0, 31].
inline std::unique_ptr<ActiveSurface> z_plane(double cell_m, float c_cells) {
    auto s = make_surface(cell_m);
    fill_set(*s, 2, 0, 0, [&](int, int) { return Intervals{{0.0f, c_cells}}; });
    return s;
}

/// Solid intervals (grid units) of the ray of set `axis` through lattice node (u, v) of a lattice with
/// cell `cell_m` (m), origin 0 and `nodes` nodes per axis.
using RayFn = std::function<Intervals(int axis, int u, int v)>;

/// A snapshot cut as compute::extract_active_surface cuts a model: stride ActiveSurface::stride_for(reach_m,
/// cell_m), windows placed around centre_m by ActiveSurface::window_first, rays from `rays`. Origin 0,
/// `nodes` nodes per axis (the lattice need not exist: only the rays in the windows are evaluated).
inline std::unique_ptr<ActiveSurface> published_surface(double cell_m, int nodes, const Vec3& centre_m, double reach_m,
                                                        const RayFn& rays) {
    auto s = make_surface(cell_m);
    s->nodes = {nodes, nodes, nodes};
    s->centre_m = centre_m;
    const int stride = ActiveSurface::stride_for(reach_m, cell_m);
    for (int a = 0; a < 3; ++a) {
        int nu = 0, nv = 0;
        const int u0 = ActiveSurface::window_first(centre_m[(a + 1) % 3] / cell_m, nodes, stride, nu);
        const int v0 = ActiveSurface::window_first(centre_m[(a + 2) % 3] / cell_m, nodes, stride, nv);
        fill_set(*s, a, u0, v0, [&](int u, int v) { return rays(a, u, v); }, stride);
        s->sets[a].nu = nu;
        s->sets[a].nv = nv;
    }
    return s;
}

/// Rays of the half-space {x : n . x <= c_m} (n unit, world m, origin 0) on a lattice of cell `cell_m` with
/// `nodes` nodes per axis: each ray's part inside the half-space, clipped to [0, nodes - 1] (grid units).
inline RayFn half_space_rays(const Vec3& n, double c_m, double cell_m, int nodes) {
    return [=](int a, int u, int v) {
        const double top = nodes - 1.0;
        const double rest = (n[(a + 1) % 3] * u + n[(a + 2) % 3] * v) * cell_m;  // n . x without the axis part
        if (n[a] == 0.0) return rest <= c_m ? Intervals{{0.0f, static_cast<float>(top)}} : Intervals{};
        const double t = (c_m - rest) / (n[a] * cell_m);  // grid units where n . x = c
        const double lo = n[a] > 0.0 ? 0.0 : std::max(0.0, t), hi = n[a] > 0.0 ? std::min(top, t) : top;
        if (!(hi > lo)) return Intervals{};
        return Intervals{{static_cast<float>(lo), static_cast<float>(hi)}};
    };
}

/// Rays of the solid ball of radius r_m about centre_m (world m, origin 0), cell `cell_m`.
inline RayFn ball_rays(const Vec3& centre_m, double r_m, double cell_m) {
    return [=](int a, int u, int v) {
        const double du = u * cell_m - centre_m[(a + 1) % 3], dv = v * cell_m - centre_m[(a + 2) % 3];
        const double h2 = r_m * r_m - du * du - dv * dv;
        if (!(h2 > 0.0)) return Intervals{};
        const double h = std::sqrt(h2);
        return Intervals{{static_cast<float>((centre_m[a] - h) / cell_m), static_cast<float>((centre_m[a] + h) / cell_m)}};
    };
}

}  // namespace tridex::test
