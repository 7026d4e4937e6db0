// compute/mesh/ply_reader.hpp - the Polygon File Format (PLY), ASCII and binary, read strictly.
#pragma once

#include <string>
#include <string_view>

#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// Reads the PLY file `path` whose bytes are `bytes` into a polygon soup: the x, y, z properties of element
/// "vertex" (file units) and the "vertex_indices" (or "vertex_index") list of element "face", fan-triangulated, in
/// file order; every other element and property is read past. Nothing is welded or checked for closure here.
/// Format (Greg Turk, "The PLY Polygon File Format"): the "ply" line; one "format ascii|binary_little_endian|
/// binary_big_endian 1.0" line before any element; "element NAME COUNT" lines, each followed by its "property TYPE
/// NAME" or "property list COUNT_TYPE ITEM_TYPE NAME" lines; "comment" and "obj_info" lines; "end_header". Types:
/// char uchar short ushort int uint float double and int8 ... float64.
/// Other header lines are taken for free text (as some exporters write). Structure is checked (a property before any
/// element, the format line missing, repeated or after an element, an unknown format or version, a float list count),
/// every
/// element and list count is checked against the bytes that remain before anything is allocated (memory stays
/// within a small multiple of the file's size), and every number against its type. Throws tridex::Error with one
/// line that starts with `path` and names the header or body line ("<path>:<line>: ...") or byte offset (binary,
/// "<path>: byte N: ...") and what is wrong; quoted file text is made printable.
TriMesh read_ply(const std::string& path, std::string_view bytes);

}  // namespace tridex::compute
