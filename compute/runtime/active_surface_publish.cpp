// compute/runtime/active_surface_publish.cpp - window extraction of the three ray sets around the tool.
#include "compute/runtime/active_surface_publish.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"

namespace tridex::compute {
namespace {

using Window = ActiveSurface::Window;
constexpr int kW = ActiveSurface::kWindow;
constexpr int kK = ActiveSurface::kMaxIntervals;

/// Indices [first, first + count) of the intervals of `ray` to publish: all of them, or the kK
/// consecutive ones nearest depth c (grid units). Sorted disjoint intervals make the kK nearest
/// consecutive, so a two-pointer walk out from c finds them exactly.
void nearest_run(const std::vector<Interval>& ray, double c, int& first, int& count) {
    const int n = static_cast<int>(ray.size());
    if (n <= kK) {
        first = 0;
        count = n;
        return;
    }
    const auto it = std::lower_bound(ray.begin(), ray.end(), c, [](const Interval& iv, double t) { return iv.exit < t; });
    int left = static_cast<int>(it - ray.begin()) - 1, right = left + 1;
    constexpr double kInf = std::numeric_limits<double>::infinity();
    for (int taken = 0; taken < kK; ++taken) {
        const double dl = left >= 0 ? c - ray[left].exit : kInf;
        const double dr = right < n ? std::max(0.0, ray[right].enter - c) : kInf;
        if (dr <= dl) ++right;
        else --left;
    }
    first = left + 1;
    count = kK;
}

// Fills window a of `out` (its stride already set) from ray set `set` around grid point g (cells).
void fill_window(const RaySet& set, const Vec3& g, ActiveSurface& out) {
    const int ax = set.axis, ua = (ax + 1) % 3, va = (ax + 2) % 3;
    Window& w = out.sets[ax];
    const int stride = out.window_spacing_cells(ax);
    w.u0 = ActiveSurface::window_first(g[ua], set.nu, stride, w.nu);
    w.v0 = ActiveSurface::window_first(g[va], set.nv, stride, w.nv);
    w.truncated = false;
    w.count.fill(0);
    for (int iv = 0; iv < w.nv; ++iv) {
        for (int iu = 0; iu < w.nu; ++iu) {
            const std::array<int, 2> uv = out.lattice_ray(ax, iu, iv);
            const auto& ray = set.ray(uv[0], uv[1]);
            int first = 0, count = 0;
            nearest_run(ray, g[ax], first, count);
            if (count < static_cast<int>(ray.size())) w.truncated = true;
            const int slot = iu + kW * iv;
            w.count[slot] = static_cast<std::uint8_t>(count);
            for (int n = 0; n < count; ++n) {
                w.depth[(slot * kK + n) * 2] = ray[first + n].enter;
                w.depth[(slot * kK + n) * 2 + 1] = ray[first + n].exit;
                w.material[slot * kK + n] = 0;  // material 0 unless painted
            }
        }
    }
}

}  // namespace

void extract_active_surface(const TriDexel& model, const Vec3& centre_m, double tool_extent_m, std::uint64_t sequence,
                            ActiveSurface& out, double motion_margin_m) {
    if (!is_finite(centre_m)) throw Error("extract_active_surface: tool centre is not finite");
    if (!(std::isfinite(tool_extent_m) && tool_extent_m >= 0.0))
        throw Error("extract_active_surface: tool_extent_m = " + std::to_string(tool_extent_m) + " must be finite and >= 0");
    if (!(std::isfinite(motion_margin_m) && motion_margin_m >= 0.0))
        throw Error("extract_active_surface: motion_margin_m = " + std::to_string(motion_margin_m) +
                    " must be finite and >= 0");
    const Lattice& L = model.lattice;
    const Vec3 g = L.to_grid(centre_m);
    const int stride = ActiveSurface::stride_for(0.5 * tool_extent_m + motion_margin_m, L.cell_m);
    out.origin_m = L.origin_m;
    out.cell_m = L.cell_m;
    out.nodes = {L.nodes(0), L.nodes(1), L.nodes(2)};
    out.centre_m = centre_m;
    for (int a = 0; a < 3; ++a) {
        out.sets[a].stride = stride;
        fill_window(model.sets[a], g, out);
    }
    out.sequence = sequence;
}

double tool_extent_m(double max_point_distance_m, double radius_m) {
    const auto ok = [](double v) { return std::isfinite(v) && v > 0.0 ? v : 0.0; };
    return 2.0 * (ok(max_point_distance_m) + ok(radius_m));
}

}  // namespace tridex::compute
