// core/active_surface.hpp - the dexel data near the tool that the haptic loop reads each tick.
// compute/ writes it (after each sculpt step), haptics/ reads it through a TripleBuffer.
#pragma once

#include <array>
#include <cstdint>

#include "core/math.hpp"

namespace tridex {

/// A fixed-size snapshot of the tri-dexel model around the tool: for each of the three ray
/// sets, a window of up to kWindow x kWindow rays centred on the tool, each with up to
/// kMaxIntervals solid intervals (the ones nearest the tool when a ray has more).
/// Ray set a holds rays parallel to axis a through lattice nodes (u, v), where u runs along
/// axis (a+1)%3 and v along axis (a+2)%3 (X rays: u=y, v=z; Y rays: u=z, v=x; Z rays: u=x, v=y).
/// Depths are in grid units (cells) along axis a from the lattice origin; world position of
/// node index i along axis k is origin_m[k] + i * cell_m. No pointers, so it copies as a block.
/// Source: Peng et al., active triangle from three dexel points around the HIP.
struct ActiveSurface {
    static constexpr int kWindow = 32;       ///< rays per side of a window
    static constexpr int kMaxIntervals = 4;  ///< intervals kept per ray

    /// The rays of one ray set inside the window.
    struct Window {
        int u0 = 0, v0 = 0;  ///< lattice indices of the window's first ray
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
};

}  // namespace tridex
