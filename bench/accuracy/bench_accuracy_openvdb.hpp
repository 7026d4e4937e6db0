// bench/accuracy/bench_accuracy_openvdb.hpp - the OpenVDB peer of `tridex bench --accuracy`: the same stroke
// programs as narrow-band level-set CSG (built only when OpenVDB was found: TRIDEX_HAVE_OPENVDB).
#pragma once

#include <string>

#include "bench/accuracy/bench_accuracy_exact.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::bench::accuracy {

/// Result of one OpenVDB run of a program.
struct PeerRun {
    std::size_t segments = 0;        ///< segments applied (same split as tridex)
    double sculpt_s = 0.0;           ///< wall time of building the tool level sets and the CSG, s
    double mesh_s = 0.0;             ///< wall time of volumeToMesh, s
    std::size_t memory_bytes = 0;    ///< FloatGrid::memUsage() of the workpiece after the program
    double volume_m3 = 0.0;          ///< tools::levelSetVolume of the workpiece, m^3
    TriMesh mesh;                    ///< volumeToMesh at isovalue 0 (quads split), m
};

/// True when this build has the OpenVDB peer.
bool openvdb_available();

/// OpenVDB version string ("" when not built with it).
std::string openvdb_version();

/// Runs `program` in OpenVDB at voxel size `voxel_m` (m) with a narrow band of `half_width` voxels and
/// voxel (0, 0, 0) at `origin_m` (the tridex lattice origin, so voxel centres coincide with lattice nodes),
/// single-threaded (tbb::global_control max_allowed_parallelism = 1, matching tridex's cpu path):
/// workpiece = createLevelSetBox of the 0.1 m cube; each segment: ball tools = spheres
/// (createLevelSetSphere) stamped along the segment at <= 0.5 voxel spacing, each combined in turn
/// (csgDifference / csgUnion; OpenVDB 10.0.1 in Debian has no createLevelSetCapsule); flat-end tools =
/// meshToLevelSet of the segment's exact swept solid (an extruded stadium, 32 segments per half circle).
/// kPaint changes no geometry in a level set, so nothing is applied (0 s). Throws tridex::Error when
/// OpenVDB is not built in.
PeerRun run_openvdb(const Program& program, double voxel_m, double half_width, const Vec3& origin_m);

}  // namespace tridex::bench::accuracy
