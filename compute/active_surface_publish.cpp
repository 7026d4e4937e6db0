// compute/active_surface_publish.cpp - window extraction of the three ray sets around the tool.
#include "compute/active_surface_publish.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace tridex::compute {
namespace {

using Window = ActiveSurface::Window;
constexpr int kW = ActiveSurface::kWindow;
constexpr int kK = ActiveSurface::kMaxIntervals;

/// First window index along an axis with `nodes` rays so the window is centred on grid coordinate g;
/// `count` receives the window size along that axis.
int window_start(double g, int nodes, int& count) {
    count = std::clamp(nodes, 0, kW);
    const double first = std::round(g) - kW / 2;
    return static_cast<int>(std::clamp(first, 0.0, static_cast<double>(std::max(0, nodes - count))));
}

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

void fill_window(const RaySet& set, const Vec3& g, Window& w) {
    const int ax = set.axis, ua = (ax + 1) % 3, va = (ax + 2) % 3;
    w.u0 = window_start(g[ua], set.nu, w.nu);
    w.v0 = window_start(g[va], set.nv, w.nv);
    w.truncated = false;
    w.count.fill(0);
    for (int iv = 0; iv < w.nv; ++iv) {
        for (int iu = 0; iu < w.nu; ++iu) {
            const auto& ray = set.ray(w.u0 + iu, w.v0 + iv);
            int first = 0, count = 0;
            nearest_run(ray, g[ax], first, count);
            if (count < static_cast<int>(ray.size())) w.truncated = true;
            const int slot = iu + kW * iv;
            w.count[slot] = static_cast<std::uint8_t>(count);
            for (int n = 0; n < count; ++n) {
                w.depth[(slot * kK + n) * 2] = ray[first + n].enter;
                w.depth[(slot * kK + n) * 2 + 1] = ray[first + n].exit;
                w.material[slot * kK + n] = 0;  // one material until painting exists (issue 3)
            }
        }
    }
}

}  // namespace

void extract_active_surface(const TriDexel& model, const Vec3& centre_m, std::uint64_t sequence, ActiveSurface& out) {
    if (!is_finite(centre_m)) throw Error("extract_active_surface: tool centre is not finite");
    const Lattice& L = model.lattice;
    const Vec3 g = L.to_grid(centre_m);
    out.origin_m = L.origin_m;
    out.cell_m = L.cell_m;
    out.nodes = {L.nodes(0), L.nodes(1), L.nodes(2)};
    out.centre_m = centre_m;
    for (int a = 0; a < 3; ++a) fill_window(model.sets[a], g, out.sets[a]);
    out.sequence = sequence;
}

}  // namespace tridex::compute
