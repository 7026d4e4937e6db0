// compute/model/islands.hpp - connected pieces of material in a box of a tri-dexel model, as the contoured mesh shows
// them, and the small ones a cut left floating (specks).
#pragma once

#include <cstddef>
#include <vector>

#include "compute/model/tridexel.hpp"
#include "core/aabb.hpp"

namespace tridex::compute {

/// Which pieces find_islands calls specks.
struct IslandOptions {
    /// Pieces wholly inside the box with a volume below this are specks, m^3 (0: none is). Sessions use
    /// speck_volume_m3 of the stroke's tool.
    double max_volume_m3 = 0.0;
};

/// One connected piece of material that find_islands found wholly inside the box.
struct IslandPiece {
    std::size_t nodes = 0;   ///< lattice nodes inside it
    /// The summed lengths of the X intervals holding its nodes times h^3 (the X rays' midpoint rule: each X ray
    /// stands for the h x h column around it, as the contour's occupancy reads them), m^3.
    double volume_m3 = 0.0;
    Aabb box_m{};            ///< world box of those X intervals, m
};

/// What find_islands found.
struct IslandSearch {
    std::size_t nodes = 0;              ///< lattice nodes inside material within the box
    std::size_t pieces = 0;             ///< connected pieces, those touching the box's sides included
    std::vector<IslandPiece> closed;    ///< pieces wholly inside the box, largest volume first
    std::vector<IslandPiece> specks;    ///< of those, the ones below IslandOptions::max_volume_m3, largest first
    double speck_volume_m3 = 0.0;       ///< summed volume of the specks, m^3
    /// The rays that hold a speck's intervals, with those intervals taken out (every other interval and every
    /// material kept), ordered by set, then by ray index: write them into the model to remove the specks.
    std::vector<RayImage> rays;
    Aabb speck_box_m{};                 ///< world box of the specks' intervals, all three sets (empty when none), m
};

/// Finds the connected pieces of material of `model` in the world box `box_m` (m) as the contoured mesh shows them,
/// and the small ones wholly inside the box (specks).
///
/// A piece is a set of lattice nodes inside material, by the contour's rule (compute/contour/contour_sample.hpp:
/// node (i, j, k) is inside when an interval of X ray (y_j, z_k) holds it, enter <= x_i < exit; nodes on the
/// lattice's border are outside), joined along lattice edges whose two nodes are inside: the contour's cells join
/// inside corners along cube edges only (compute/contour/contour_table.hpp), so each piece is bounded by its own
/// components of the contoured mesh and each speck removed is one mesh component fewer. Found as runs: the nodes an X interval holds are one run; runs on one ray whose nodes
/// are adjacent, and runs on 4-neighbour X rays holding a common node index, are joined (union-find). Material that
/// holds no lattice node is not seen (nor drawn: the contour has no sign change there); a sheet thinner than the
/// lattice resolves, slanted across it, falls apart into pieces here as it does in the mesh.
///
/// A piece touches the box's sides when one of its nodes lies on a side inside the lattice (the node beyond may be
/// inside material); such a piece may go on outside the box and is never reported as closed. A piece's material is
/// the intervals of all three sets holding its nodes (each interval holds nodes of one piece only, since two inside
/// nodes on one interval are joined along their ray); `rays` removes exactly those from the specks.
/// Cost: O(X intervals in the box) to find and measure the pieces, plus O(nodes x log intervals per ray) for the
/// specks' Y and Z intervals.
/// Throws tridex::Error for a non-finite box or a negative or non-finite max_volume_m3; an empty box or one beside
/// the lattice finds nothing.
IslandSearch find_islands(const TriDexel& model, const Aabb& box_m, const IslandOptions& options);

/// The speck threshold for a tool of radius `tool_radius_m` (m): the volume of that ball, 4/3 pi r^3, m^3. A piece
/// a cut leaves floating that is smaller than the ball which cut it is debris; a chunk larger than the tool that the
/// user sliced off on purpose stays. 0 for a radius that is not finite and positive.
double speck_volume_m3(double tool_radius_m);

}  // namespace tridex::compute
