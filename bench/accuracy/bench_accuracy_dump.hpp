// bench/accuracy/bench_accuracy_dump.hpp - `tridex bench --accuracy --accuracy-dump K`: the K worst mesh vertices of a
// tridex run with what contouring saw in their cells (crossings, estimated normals) against the exact solid.
#pragma once

#include "bench/accuracy/bench_accuracy_exact.hpp"
#include "compute/model/tridexel.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::bench::accuracy {

/// Prints to stdout the `k` mesh vertices of `mesh` (world m, contoured from `model`) with the largest |sdf| of
/// `exact`, each with: its grid position and error (cells), the exact outward normal there (central difference
/// of the SDF), and for the cell holding it (floor of the grid position; for a vertex on
/// a cell face also the cell below that face, when it holds surface) every sign-change edge with its
/// crossing (grid units), whether the crossing came from a fallback, its estimated normal
/// (contour::crossing_normal, "-" when none, "crease" when a crease's flat side gave it) and the exact normal
/// and signed distance (cells) at the crossing, then the interval ends within three cells of it on the four rays
/// beside its edge (those crossing_normal reads); a vertex on a lattice line (an edge crossing or split-face
/// vertex) also gets the intervals of that line's ray. Vertices
/// closer than one cell to an already printed one are skipped. A diagnostic: O(V log V + k).
void dump_worst_vertices(const compute::TriDexel& model, const TriMesh& mesh, const ExactSolid& exact, int k);

}  // namespace tridex::bench::accuracy
