// bench/bench_wall.cpp - a half-space snapshot and a press-hold-release path.
#include "bench/bench_wall.hpp"

namespace tridex::bench {

std::unique_ptr<ActiveSurface> bench_wall_surface() {
    auto s = std::make_unique<ActiveSurface>();
    s->sequence = 1;
    s->cell_m = 1e-3;
    s->origin_m = Vec3(-0.016, -0.016, -0.020);
    s->nodes = {64, 64, 64};
    s->centre_m = Vec3(0.0);
    ActiveSurface::Window& w = s->sets[2];
    w.nu = w.nv = ActiveSurface::kWindow;
    for (int i = 0; i < ActiveSurface::kWindow * ActiveSurface::kWindow; ++i) {
        w.count[i] = 1;
        w.depth[i * ActiveSurface::kMaxIntervals * 2] = 0.0f;
        w.depth[i * ActiveSurface::kMaxIntervals * 2 + 1] = 20.0f;
    }
    return s;
}

devices::ScriptedPath bench_wall_press(double depth_m) {
    // Catmull-Rom tangents: the doubled waypoints at each end of the hold keep it flat from 0.4 to 1.4 s.
    const Vec3 up(0.0, 0.0, 0.010), in(0.0, 0.0, -depth_m);
    return devices::ScriptedPath({0.0, 0.3, 0.4, 1.4, 1.5, 1.8, 2.5}, {up, in, in, in, in, up, up});
}

}  // namespace tridex::bench
