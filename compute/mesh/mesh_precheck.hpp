// compute/mesh/mesh_precheck.hpp - cheap sanity checks of a mesh file before any parser sees it.
#pragma once

#include <string>

namespace tridex::compute {

/// The mesh file formats load_closed_mesh accepts.
enum class MeshFormat { kOff, kObj, kPly, kStl };

/// The format named by the extension of `path` (case-insensitive: .off, .obj, .ply, .stl).
/// Throws tridex::Error "<path>: unknown mesh file extension '<ext>' (expected .off, .obj, .ply or .stl)".
MeshFormat mesh_format_of(const std::string& path);

/// Reads only what is needed to prove that the file cannot make OpenMesh allocate absurd amounts of memory or
/// index out of range, so that OpenMesh is never handed such a file:
/// - any format: the file exists, is a regular file, is readable, and is not empty;
/// - STL: binary files have exactly 84 + 50 * count bytes and finite coordinates; ASCII files start with "solid";
/// - OBJ: every face line has >= 3 vertex references, each a non-zero integer (negative = relative)
///   resolving to a vertex defined before it.
/// OFF and PLY files are read by tridex's own strict readers (read_off, read_ply), which check as they go.
/// Throws tridex::Error "<path>: <reason>" (with ":<line>" for OBJ) on the first problem found; quoted file text is
/// made printable. Cost: O(1) for OFF/PLY, O(file) for STL and OBJ.
void precheck_mesh_file(const std::string& path, MeshFormat format);

}  // namespace tridex::compute
