// compute/model/volume.hpp - the volume of a tri-dexel solid.
#pragma once

#include "compute/model/tridexel.hpp"

namespace tridex::compute {

/// Volume of the solid, m^3: the three ray sets' estimates (ray_set_volume_m3 plus
/// lattice_face_correction_m3 for each), averaged. Exact for axis-aligned boxes anywhere on the
/// lattice; otherwise a midpoint-rule estimate whose error shrinks as h^2 for smooth surfaces,
/// including cuts into flat axis-aligned faces at any offset from the nodes.
/// O(intervals). Never throws.
double dexel_volume_m3(const TriDexel& model);

/// Raw volume of one ray set, m^3: the sum of its interval lengths (grid units, summed in double) times
/// h^3, each ray standing for the h x h column around its node (the midpoint rule across the rays).
/// `axis` must be 0, 1 or 2, else throws tridex::Error.
double ray_set_volume_m3(const TriDexel& model, int axis);

/// Correction of ray_set_volume_m3(model, axis) for faces and walls parallel to the rays, m^3 (add it
/// to the raw volume).
///
/// Why: a flat face parallel to this set's rays (a workpiece face, the flat floor of a cut) lies
/// between two rows of rays, or on one. The midpoint rule counts the column of the row nearest the
/// face as all material or none, so the set sees the face moved to the column's edge (up to half a
/// cell; on a face through nodes the ties of scan conversion decide). For a closed box the opposite
/// faces cancel; a cut that changes one face's area no longer cancels, and the raw volume is off by
/// up to (area cut from the face) x h/2, an error of order h.
///
/// Rule: where a ray of another set e has an interval end at depth t and e's ray through a neighbour
/// node along this set's axis ends at exactly the same depth (a surface parallel to the rays; a
/// sloped or curved surface crossing them does not do that), the column of node m = round(t) on this
/// set's ray through it is given the share of it that lies on the material side of t (t - m + 1/2 at
/// an exit, m + 1/2 - t at an entry) instead of the 0 or 1 that the ray's coverage of the node
/// (enter <= m < exit) counts. Full weight when e's rays also keep the depth along the third axis b
/// (a flat face perpendicular to e, which b's rays lie in); half weight otherwise (a sloped or curved
/// wall parallel to the rays, which e's and b's rays both cross, so each corrects half).
/// Axis-aligned boxes anywhere keep their exact volume (opposite faces' corrections cancel).
/// Limits: a node on an edge parallel to the rays is seen by both other sets and corrected by each
/// (exact for boxes, where the edges cancel; up to h^3/2 per such node elsewhere); a face or wall one node wide is not seen; on a curved wall
/// the share along one axis stands for the column's area share (first order in h).
/// O(intervals x intervals per ray). `axis` must be 0, 1 or 2, else throws tridex::Error.
double lattice_face_correction_m3(const TriDexel& model, int axis);

}  // namespace tridex::compute
