// compute/model/model_digest.hpp - a 64-bit digest of a tri-dexel model's contents, for checking that two copies of a
// model (a cluster's ranks) hold the same solid bit for bit.
#pragma once

#include <cstdint>
#include <string>

#include "compute/model/tridexel.hpp"

namespace tridex::compute {

/// FNV-1a (64-bit) over the lattice's size and, for each ray set in axis order and each ray in index order, the
/// ray's interval count and each interval's enter and exit (the float's bits) and materials. Equal models give equal
/// digests; models that differ in any interval end, material or count differ in the digest but for a 2^-64 chance.
/// Dirty flags are not part of it. O(rays + intervals): about a millisecond per million intervals.
std::uint64_t model_digest(const TriDexel& model);

/// A digest as 16 lower-case hex digits, for messages.
std::string digest_hex(std::uint64_t digest);

}  // namespace tridex::compute
