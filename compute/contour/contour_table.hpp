// compute/contour/contour_table.hpp - the 256 corner configurations of a lattice cell and the surface
// components (dual vertices) each one holds, for manifold dual contouring.
#pragma once

#include <array>
#include <cstdint>

namespace tridex::compute::contour {

// Numbering used by the whole contouring code (grid units, one cell = unit cube):
//  - corner c (0..7) of a cell sits at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1) from the cell's
//    min node; bit c of a configuration byte is 1 when that corner node is inside the solid;
//  - cube edge e (0..11) = 4*a + ob + 2*oc runs along axis a from offset 0 to 1, at offset ob along
//    axis (a+1)%3 and oc along axis (a+2)%3;
//  - face f (0..5) = 2*a + side is the cell face perpendicular to axis a at offset `side`.

/// Most surface components one cell can hold (four isolated corners in tetrahedral position).
inline constexpr int kMaxComponents = 4;

/// What one corner configuration contains.
struct CellCase {
    /// Number of surface components (dual vertices) of the cell, 0..kMaxComponents.
    std::uint8_t components = 0;
    /// Per cube edge: the component whose surface crosses it, or -1 when the edge has no sign change.
    std::array<std::int8_t, 12> edge_component{};
    /// Bit f: face f is ambiguous (inside corners on one diagonal, outside on the other) and both of
    /// its surface segments belong to the same component of this cell. When the cells on both sides of
    /// a face have this bit, one dual edge would stand for two segments; the tile contourer then splits
    /// that face (see contour_tile.hpp).
    std::uint8_t merged_faces = 0;
};

/// The table for all 256 configurations, built once by cell_cases_build() on first use.
///
/// Connectivity rule (consistent on every face, so the two cells sharing a face agree): inside corners
/// connect only along cube edges; outside corners connect along cube edges and across an ambiguous face
/// (its two outside corners); never across the body diagonal. A surface component is one pair
/// (inside corner group, outside corner group) joined by at least one sign-change edge; each such pair
/// meets along exactly one loop on the cell's boundary, so it is one disc-like patch (the cell part of a
/// marching-cubes surface with this face rule), and gets one dual vertex (manifold dual contouring:
/// Schaefer, Ju, Warren 2007; Nielson "Dual Marching Cubes" 2004 - idea only).
const std::array<CellCase, 256>& cell_cases();

/// The two corners of cube edge e (0..11): first at offset 0 along the edge's axis, second at offset 1.
std::array<int, 2> edge_corners(int e);

/// The four corners of face f (0..5), in the order o1 + 2*o2 of their offsets along the face's in-plane
/// axes (f/2+1)%3 and (f/2+2)%3.
std::array<int, 4> face_corners(int f);

/// True when face f of configuration `config` is ambiguous: its inside corners are exactly one diagonal.
bool face_ambiguous(int config, int f);

}  // namespace tridex::compute::contour
