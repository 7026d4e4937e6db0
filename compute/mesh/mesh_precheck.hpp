// compute/mesh/mesh_precheck.hpp - cheap sanity checks of a mesh file before any parser sees it.
#pragma once

#include <string>

namespace tridex::compute {

/// The mesh file formats load_closed_mesh accepts.
enum class MeshFormat { kOff, kObj, kPly, kStl };

/// The format named by the extension of `path` (case-insensitive: .off, .obj, .ply, .stl).
/// Throws tridex::Error "<path>: unknown mesh file extension '<ext>' (expected .off, .obj, .ply or .stl)".
MeshFormat mesh_format_of(const std::string& path);

/// Reads only what is needed to prove that the file cannot make a parser allocate absurd amounts of
/// memory or index out of range, so that OpenMesh is never handed such a file:
/// - any format: the file exists, is readable, and is not empty;
/// - OFF: keyword line, vertex/face counts are integers, and the file is big enough to hold that many
///   vertices and faces (ASCII: >= 2 bytes per number; BINARY: 4 bytes per number); in ASCII files
///   every vertex line starts with three finite numbers ("<path>:<line>: vertex N coordinate 'nan' ...");
/// - PLY: "ply" magic, a known format line, element counts that the remaining bytes can hold;
/// - STL: binary files have exactly 84 + 50 * count bytes; ASCII files start with "solid";
/// - OBJ: every face line has >= 3 vertex references, each a non-zero integer (negative = relative)
///   resolving to a vertex defined before it.
/// Throws tridex::Error "<path>: <reason>" (with ":<line>" for OBJ) on the first problem found.
/// Cost: O(header) for OFF/PLY/STL, one pass over the file for OBJ.
void precheck_mesh_file(const std::string& path, MeshFormat format);

}  // namespace tridex::compute
