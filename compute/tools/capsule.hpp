// compute/tools/capsule.hpp - the chord of a line through a capsule (the swept volume of a moving ball).
#pragma once

#include <glm/glm.hpp>

namespace tridex::compute {

/// Chord of the line {o + t*d} (d unit or not; t in the units of o per unit of d) with the capsule
/// (segment a-b, radius r): returns false if the line misses it (or d is zero, or r <= 0 or NaN),
/// else true with t0 <= t1 (t0 == t1 for a tangent line). Closed form: the union of the two end-ball
/// chords and the finite-cylinder chord (the capsule is convex, so the union is one interval).
/// Arithmetic: float only, no fused multiply-add (the build uses -ffp-contract=off), dot and cross
/// products written out left to right, discriminants in the cross-product form
/// (ball: |d|^2 r^2 - |m x d|^2; cylinder via Lagrange's identity), so a GPU shader can reproduce it
/// bit for bit. Pass coordinates relative to a local origin near the tool (e.g. the segment start)
/// to keep float precision. Source: Peng et al., tri-dexel Booleans with a ball tool's sweep.
bool capsule_chord(glm::vec3 o, glm::vec3 d, glm::vec3 a, glm::vec3 b, float r, float& t0, float& t1);

/// Chord of the line {o + t*d} with the solid finite cylinder of radius r whose axis runs from a to
/// a + e, closed by flat caps at both ends (a flat-end mill: a is the centre of the flat end, e the
/// shank). Same contract and arithmetic rules as capsule_chord; false when the line misses it, d or e
/// is zero, or r <= 0 or NaN. The cylinder is convex, so the chord is one interval.
bool cylinder_chord(glm::vec3 o, glm::vec3 d, glm::vec3 a, glm::vec3 e, float r, float& t0, float& t1);

}  // namespace tridex::compute
