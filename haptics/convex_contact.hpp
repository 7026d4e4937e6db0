// haptics/convex_contact.hpp - a ball's contact with a convex edge or corner of the snapshot, where no face lies
// under the ball's centre.
#pragma once

#include <array>

#include "core/active_surface.hpp"
#include "haptics/constraint_plane.hpp"

namespace tridex::haptics::contact {

/// The 26 unit directions from a cell to its neighbours in a 3 x 3 x 3 block (axes, face diagonals, corner
/// diagonals): where a ball is sampled for material around it.
const std::array<Vec3, 26>& ball_directions();

/// The plane a ball of radius radius_m (m, > 0) centred on `hip` (m) is held back by at a convex edge or corner the
/// plane search finds no face for: the faces around the ball are gathered from the active triangles under the points
/// hip + r*u and hip + 1.5*r*u (u the 26 axis, face-diagonal and corner directions) that lie in material, the solid near
/// them is taken as the intersection of their half-spaces (valid for a convex feature; any pair of faces that is
/// not convex, one's triangle outside the other's half-space, means a concave one and gives false), and the point
/// x* of that intersection nearest the HIP is found exactly (projection on every face, edge line and corner of up to
/// three active faces). Zilles & Salisbury's god-object for a ball is its centre on the solid grown by r nearest
/// the HIP: at an edge that grown solid is a cylinder about the edge, so the plane returned is its tangent plane,
/// normal n = (hip - x*) / |hip - x*|, through x* (Triangle::on), depth r - |hip - x*| (> 0 when true). The
/// triangle's other fields are those of the nearest face (its set in PlaneSearch::axis, materials, weights).
/// False when the radius is not > 0, no point of the ball lies inside material, the HIP lies inside every face's
/// half-space (the centre is in material: the plane search's case), the ball does not reach x*, or the previous
/// `proxy` (m) already overlapped the feature by more than a quarter window spacing (the god-object's constraint
/// test), or fewer than `min_faces` distinct faces were found (2: only a true edge or corner). Allocation-free; reads 52 points and the active triangles under those in material.
bool convex_feature_plane(const ActiveSurface& surface, const Vec3& hip, const Vec3& proxy, double radius_m,
                          int min_faces, PlaneSearch& out);

}  // namespace tridex::haptics::contact
