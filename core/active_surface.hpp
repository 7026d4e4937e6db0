// core/active_surface.hpp - the dexel data near the tool that the haptic loop reads each tick.
// compute/ writes it (after each sculpt step), haptics/ reads it through a TripleBuffer.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/math.hpp"

namespace tridex {

/// A fixed-size snapshot of the tri-dexel model around the tool: for each of the three ray
/// sets, a window of up to kWindow x kWindow rays centred on the tool, each with up to
/// kMaxIntervals solid intervals (the ones nearest the tool when a ray has more).
/// Ray set a holds rays parallel to axis a through lattice nodes (u, v), where u runs along
/// axis (a+1)%3 and v along axis (a+2)%3 (X rays: u=y, v=z; Y rays: u=z, v=x; Z rays: u=x, v=y).
/// A window samples every `stride`-th lattice ray: window-local ray (iu, iv) is lattice ray
/// (u0 + stride*iu, v0 + stride*iv), so a window spans (kWindow-1)*stride cells whatever the lattice
/// (the publisher picks the stride from the tool's extent). Depths stay in grid units (cells of the
/// lattice, not of the window) along axis a from the lattice origin; world position of node index i
/// along axis k is origin_m[k] + i * cell_m. Every world <-> window conversion goes through
/// to_window() / window_point() / window_spacing_cells() (no stride maths elsewhere).
/// No pointers, so it copies as a block (about 111 KB).
/// Source: Peng et al., active triangle from three dexel points around the HIP.
struct ActiveSurface {
    static constexpr int kWindow = 32;       ///< rays per side of a window
    static constexpr int kMaxIntervals = 4;  ///< intervals kept per ray
    /// Window rays guaranteed on each side of the centre the publisher was given (window_first()
    /// rounds the centre to the nearest strided ray): every point within kCoverRays * stride * cell_m
    /// (per axis) of the centre projects inside the window unless the lattice ends first.
    static constexpr double kCoverRays = kWindow / 2 - 1.5;

    /// The rays of one ray set inside the window.
    struct Window {
        int u0 = 0, v0 = 0;  ///< lattice indices of the window's first ray
        int stride = 1;      ///< lattice rays between neighbouring window rays, >= 1 (1 = every ray)
        int nu = 0, nv = 0;  ///< rays filled along u and v (<= kWindow); 0 = empty window
        bool truncated = false;  ///< some ray had more than kMaxIntervals intervals
        std::array<std::uint8_t, kWindow * kWindow> count{};  ///< intervals per ray, index iu + kWindow*iv
        /// [enter, exit] pairs, grid units, index ((iu + kWindow*iv) * kMaxIntervals + n) * 2 + {0,1}
        std::array<float, kWindow * kWindow * kMaxIntervals * 2> depth{};
        /// Material id of each interval (index (iu + kWindow*iv) * kMaxIntervals + n); 0 = the workpiece's
        /// own material. Haptics looks up stiffness, damping and friction per material.
        std::array<std::uint8_t, kWindow * kWindow * kMaxIntervals> material{};

        /// Number of intervals on the ray at window-local (iu, iv).
        int intervals(int iu, int iv) const { return count[iu + kWindow * iv]; }
        /// Entry depth (grid units) of interval n on the ray at (iu, iv).
        float enter(int iu, int iv, int n) const { return depth[((iu + kWindow * iv) * kMaxIntervals + n) * 2]; }
        /// Exit depth (grid units) of interval n on the ray at (iu, iv).
        float exit(int iu, int iv, int n) const { return depth[((iu + kWindow * iv) * kMaxIntervals + n) * 2 + 1]; }
        /// Material id of interval n on the ray at (iu, iv).
        std::uint8_t material_of(int iu, int iv, int n) const { return material[(iu + kWindow * iv) * kMaxIntervals + n]; }
    };

    std::uint64_t sequence = 0;       ///< increments on every publish; 0 = nothing published yet
    /// Which tool samples the model held when it was read: ToolSample::made_s (steady-clock s) of the newest sample
    /// applied; -infinity when none was applied yet (every later sample is newer); NaN when unknown (a publisher that
    /// does not say, or samples without made_s). The haptic loop takes its own subtracting sweeps made after it as
    /// cut already (haptics/recent_cuts.hpp); NaN turns that off.
    double applied_made_s = std::numeric_limits<double>::quiet_NaN();
    Vec3 origin_m{0.0};               ///< world position of lattice node (0,0,0), m
    double cell_m = 0.0;              ///< lattice spacing h, m
    std::array<int, 3> nodes{};       ///< lattice node count along x, y, z
    Vec3 centre_m{0.0};               ///< tool position the windows are centred on, m
    std::array<Window, 3> sets{};     ///< windows of the X, Y and Z ray sets

    /// World position (m) of the point at depth d (grid units) on the ray of set a at lattice node (u, v).
    Vec3 point(int a, int u, int v, double d) const {
        Vec3 g;
        g[a] = d;
        g[(a + 1) % 3] = u;
        g[(a + 2) % 3] = v;
        return origin_m + cell_m * g;
    }

    /// A world point in the frame of one ray set's window.
    struct WindowCoord {
        double fu = 0.0, fv = 0.0;  ///< window-local ray coordinates (ray spacings): lattice u = u0 + stride*fu
        double d = 0.0;             ///< depth along the set's axis, grid units of the lattice
    };
    /// Window-local coordinates of world point p_m (m) for ray set a (0..2). The HIP's window cell is
    /// (floor(fu), floor(fv)); p lies over the window's rays when 0 <= fu <= nu-1 and 0 <= fv <= nv-1.
    /// No checks: a non-finite p or cell gives non-finite coordinates.
    WindowCoord to_window(int a, const Vec3& p_m) const {
        const Window& w = sets[a];
        const int ua = (a + 1) % 3, va = (a + 2) % 3;
        const int s = window_spacing_cells(a);
        return {((p_m[ua] - origin_m[ua]) / cell_m - w.u0) / s, ((p_m[va] - origin_m[va]) / cell_m - w.v0) / s,
                (p_m[a] - origin_m[a]) / cell_m};
    }
    /// World position (m) of the point at depth d (grid units) on window-local ray (iu, iv) of set a.
    Vec3 window_point(int a, int iu, int iv, double d) const {
        const std::array<int, 2> uv = lattice_ray(a, iu, iv);
        return point(a, uv[0], uv[1], d);
    }
    /// Lattice node (u, v) of window-local ray (iu, iv) of set a: (u0 + stride*iu, v0 + stride*iv).
    std::array<int, 2> lattice_ray(int a, int iu, int iv) const {
        const Window& w = sets[a];
        const int s = window_spacing_cells(a);
        return {w.u0 + s * iu, w.v0 + s * iv};
    }
    /// Spacing of set a's window rays in lattice cells: its stride (a stride below 1 counts as 1).
    /// Multiply by cell_m for metres.
    int window_spacing_cells(int a) const { return sets[a].stride > 1 ? sets[a].stride : 1; }

    /// Smallest stride >= 1 with kCoverRays * stride * cell_m >= reach_m: the stride at which a window
    /// covers every point within reach_m (m, per axis) of its centre. 1 when reach_m or cell_m is not
    /// positive and finite; at most 1 << 20.
    static int stride_for(double reach_m, double cell_m) {
        if (!(reach_m > 0.0 && cell_m > 0.0) || !(reach_m < 1e300) || !(cell_m < 1e300)) return 1;
        const double s = reach_m / (kCoverRays * cell_m);
        if (!(s > 1.0)) return 1;
        if (!(s < static_cast<double>(1 << 20))) return 1 << 20;
        const int i = static_cast<int>(s);
        return i < s ? i + 1 : i;
    }
    /// Where a window belongs (world m): on the god-object `proxy_m`, so a hand pushed into material does not drag
    /// the window away from the proxy it constrains, unless a window there, with the stride
    /// stride_for(half_extent_m + margin_m, cell_m), would not cover the tool (half_extent_m, m, about its centre)
    /// at the HIP `hip_m`: then on the HIP, so the contact sees where the hand went and the proxy can find the
    /// surface there. A non-finite proxy gives the HIP; a negative or non-finite extent or margin counts as 0.
    static Vec3 window_centre_m(const Vec3& proxy_m, const Vec3& hip_m, double half_extent_m, double margin_m,
                                double cell_m) {
        if (!(std::isfinite(proxy_m.x) && std::isfinite(proxy_m.y) && std::isfinite(proxy_m.z))) return hip_m;
        const double half = half_extent_m > 0.0 && half_extent_m < 1e300 ? half_extent_m : 0.0;
        const double margin = margin_m > 0.0 && margin_m < 1e300 ? margin_m : 0.0;
        const double cover = kCoverRays * stride_for(half + margin, cell_m) * cell_m - half;
        const Vec3 off = glm::abs(hip_m - proxy_m);
        return off.x > cover || off.y > cover || off.z > cover ? hip_m : proxy_m;
    }
    /// Placement of a window along one lattice axis with `nodes` rays (>= 0) at stride `stride` (>= 1):
    /// the first ray's lattice index for a window centred on grid coordinate g (cells), and in `count`
    /// the number of window rays (min(kWindow, rays at that stride)). The first ray is the strided ray
    /// nearest g minus kWindow/2 strides (a multiple of stride, so re-centring keeps the same rays),
    /// clamped so the window stays inside [0, nodes-1]. Non-finite g clamps to an end.
    static int window_first(double g, int nodes, int stride, int& count) {
        const int rays = nodes > 0 ? (nodes - 1) / stride + 1 : 0;
        count = rays < kWindow ? rays : kWindow;
        const double first = (std::round(g / stride) - kWindow / 2) * stride;
        const double last = nodes > 0 ? static_cast<double>(nodes - 1 - stride * (count - 1)) : 0.0;
        if (!(first > 0.0)) return 0;  // also NaN
        return static_cast<int>(first < last ? first : last);
    }
};

}  // namespace tridex
