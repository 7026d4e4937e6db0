// compute/mesh/off_reader.hpp - the Object File Format (Geomview OFF), ASCII and binary, read strictly.
#pragma once

#include <string>
#include <string_view>

#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// Reads the OFF file `path` whose bytes are `bytes` into a polygon soup: the vertex positions (file units) and the
/// faces fan-triangulated, in file order; nothing is welded or checked for closure here.
/// Format (Geomview's OOGL manual, "OFF"): the header keyword [ST][C][N][4][n]OFF (optional; "nOFF" is followed by
/// the dimension), then the vertex, face and edge counts, the vertices (dimension coordinates, then a normal with N,
/// an RGBA colour with C, texture coordinates with ST; 4OFF adds a homogeneous coordinate, divided out) and the
/// faces ("k i0 ... ik-1", a colour to the end of the line ignored); '#' comments anywhere in ASCII. "OFF BINARY"
/// (manual, "Binary format"): after the header line, big-endian 32-bit integers and IEEE floats; each face is k,
/// its k indices, a colour count (0 to 4) and that many floats.
/// Every count is checked against the bytes that remain before anything is allocated, so memory stays within a
/// small multiple of the file's size. Throws tridex::Error with one line that starts with `path` and names the line
/// (ASCII, "<path>:<line>: ...") or byte offset (binary, "<path>: byte N: ...") and what is wrong; quoted file text
/// is made printable.
TriMesh read_off(const std::string& path, std::string_view bytes);

}  // namespace tridex::compute
