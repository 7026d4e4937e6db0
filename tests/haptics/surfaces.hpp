// tests/haptics/surfaces.hpp - hand-built ActiveSurface snapshots for the haptics tests.
#pragma once

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

/// Fills the whole kWindow x kWindow window of ray set `axis`, first ray at lattice (u0, v0), with the
/// intervals rays(u, v) returns for lattice indices (u, v).
inline void fill_set(ActiveSurface& s, int axis, int u0, int v0, const std::function<Intervals(int, int)>& rays) {
    ActiveSurface::Window& w = s.sets[axis];
    w.u0 = u0;
    w.v0 = v0;
    w.nu = ActiveSurface::kWindow;
    w.nv = ActiveSurface::kWindow;
    for (int iv = 0; iv < w.nv; ++iv)
        for (int iu = 0; iu < w.nu; ++iu) {
            const Intervals in = rays(u0 + iu, v0 + iv);
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

}  // namespace tridex::test
