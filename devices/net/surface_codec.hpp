// devices/net/surface_codec.hpp - an ActiveSurface snapshot as a kSurface datagram: only the filled rays of
// each window are sent (a ray count, then per ray its intervals and materials), so a snapshot near a
// surface is a few KB instead of the struct's ~111 KB.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/active_surface.hpp"
#include "devices/net/link_wire.hpp"

namespace tridex::devices::net {

/// Writes header h (type set to kSurface) and snapshot s into out (cleared first). Rays past a window's
/// nu x nv are not sent.
void encode_surface(Header h, const ActiveSurface& s, std::vector<std::uint8_t>& out);

/// Reads a kSurface datagram (p, n: the whole datagram, header already checked) into out, every window
/// field overwritten (rays beyond nu x nv get count 0). kNone on success; kBadLength on a short or long
/// payload, kNonFinite on a non-finite origin, cell, centre or depth, kOutOfRange on a window bigger than
/// kWindow, a stride < 1, more than kMaxIntervals intervals on a ray, a cell <= 0 or a node count < 0.
/// On failure out is unspecified.
DropReason decode_surface(const std::uint8_t* p, std::size_t n, ActiveSurface& out);

}  // namespace tridex::devices::net
