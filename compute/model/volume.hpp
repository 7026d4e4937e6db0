// compute/model/volume.hpp - the volume of a tri-dexel solid.
#pragma once

#include "compute/model/tridexel.hpp"

namespace tridex::compute {

/// Volume of the solid, m^3: the three ray sets' estimates (ray_set_volume_m3 plus
/// lattice_face_correction_m3 for each), averaged. Exact for solids whose faces are all lattice planes
/// (boxes and unions of boxes with faces on or between nodes); otherwise a midpoint-rule estimate whose
/// error shrinks as h^2 for smooth surfaces, including cuts into faces that lie on lattice nodes.
/// O(intervals). Never throws.
double dexel_volume_m3(const TriDexel& model);

/// Raw volume of one ray set, m^3: the sum of its interval lengths (grid units, summed in double) times
/// h^3, each ray standing for the h x h column around its node (the midpoint rule across the rays).
/// `axis` must be 0, 1 or 2, else throws tridex::Error.
double ray_set_volume_m3(const TriDexel& model, int axis);

/// Trapezoid-rule correction of ray_set_volume_m3(model, axis) for surfaces that lie in a lattice
/// plane parallel to the rays, m^3 (add it to the raw volume).
///
/// Why: such a face (a workpiece face on nodes, the flat floor of a cut at a whole-cell depth) holds a
/// row of rays exactly; scan conversion and the Booleans put each such ray wholly inside or outside,
/// so the midpoint rule counts the face's column row as all or nothing and the set sees the face half
/// a cell off. For a closed box the two opposite faces cancel; a cut that changes one face's
/// area no longer cancels, and the raw volume is off by (area cut from the face) x h/2, an error of
/// order h. The trapezoid rule gives such rays half weight instead.
///
/// Rule: a node n lies on such a face when the ray of another set e has an interval end exactly on it
/// (a whole grid unit) and so does e's ray through a neighbour of n along this set's axis (the face
/// continues along the rays; a sloped surface through nodes does not). Each such (node, other set)
/// pair adds -h^3/2 when this set's ray covers the node (enter <= depth < exit) and +h^3/2 when it
/// does not. For scan-converted solids bounded by lattice planes the entry and exit faces cancel
/// exactly, so boxes keep their exact volume.
/// Limits: a node on an edge parallel to the rays, or on a lattice-diagonal plane that contains the
/// rays, is seen by both other sets and gets the correction twice (exact for boxes, where the edges
/// cancel; an error of h^3/2 per such node elsewhere); a face one node wide is not seen.
/// O(intervals x intervals per ray at the ends that lie on nodes). `axis` must be 0, 1 or 2, else
/// throws tridex::Error.
double lattice_face_correction_m3(const TriDexel& model, int axis);

}  // namespace tridex::compute
