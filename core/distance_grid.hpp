// core/distance_grid.hpp - a signed distance field sampled on a regular grid: how far a point lies from a closed
// surface (negative inside). compute/ builds it from a mesh; the haptic loop reads it to feel a rigid object.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "core/math.hpp"

namespace tridex {

/// Signed distance (m) to a closed surface, stored at the nodes origin_m + cell_m * (i, j, k) of a regular grid in
/// the surface's own frame: negative inside the solid, positive outside, 0 on the surface. Built by
/// compute/contour/distance_grid_build.hpp; read without allocating (the haptic thread samples it every tick).
struct DistanceGrid {
    Vec3 origin_m{0.0};             ///< position of node (0, 0, 0) in the surface's frame, m
    double cell_m = 0.0;            ///< node spacing, m, > 0
    std::array<int, 3> nodes{};     ///< nodes along x, y, z, each >= 2
    std::vector<float> distance_m;  ///< signed distance per node, m; index i + nodes[0] * (j + nodes[1] * k)

    /// Index of node (i, j, k) in distance_m (no range check).
    std::size_t index(int i, int j, int k) const {
        return static_cast<std::size_t>(i) +
               static_cast<std::size_t>(nodes[0]) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(nodes[1]) * k);
    }
    /// True when the grid is usable: spacing finite and > 0, at least 2 nodes per axis, one value per node.
    bool valid() const;
    /// The trilinear interpolant at p_m (the surface's frame, m): its value `distance` (m) and its analytic
    /// gradient `gradient` (dimensionless; about unit length where the field is a true distance). False, with the
    /// outputs untouched, when p_m is not finite or lies outside the grid's box. O(1); allocates nothing.
    /// The interpolation error of a smooth surface with curvature radius R is about cell_m^2 / (8 R).
    bool sample(const Vec3& p_m, double& distance, Vec3& gradient) const;
    /// Bytes of the samples.
    std::size_t bytes() const { return distance_m.size() * sizeof(float); }
};

}  // namespace tridex
