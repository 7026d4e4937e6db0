// compute/tools/mesh_tool.hpp - any closed mesh as a cutting tool: its own tri-dexel model per orientation.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/aabb.hpp"
#include "core/math.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// One ray set of a tool's dexel model, axis-aligned with the WORLD (the tool already rotated), with
/// lateral spacing h = cell / k. Tool ray (i, j) (i along (axis+1)%3, j along (axis+2)%3) passes
/// through the point that lies ((i - ref_u)/k, (j - ref_v)/k) workpiece cells from the tool's reference
/// point laterally. Its solid intervals are [depth[2q], depth[2q+1]] for q in [first[i + nu*j],
/// first[i + nu*j + 1]), in workpiece cells along the axis, relative to the reference point, sorted.
struct ToolDexelSet {
    int nu = 0;     ///< tool rays along u
    int nv = 0;     ///< tool rays along v
    int ref_u = 0;  ///< index i of the rays through the reference point
    int ref_v = 0;  ///< index j of the rays through the reference point
    std::vector<std::uint32_t> first;  ///< nu*nv + 1 prefix offsets into the intervals
    std::vector<float> depth;          ///< 2 floats per interval (enter, exit), workpiece cells
};

/// A mesh tool's dexels for one orientation (a rotation) and one workpiece cell size. Immutable once built.
struct ToolDexels {
    int k = 4;               ///< tool rays per workpiece cell (h = cell_m / k)
    double cell_m = 0.0;     ///< workpiece cell size it was built for, m
    Vec3 axis{0.0, 0.0, 1.0};  ///< unit world direction the tool frame's +z was turned to (rotation * +z)
    glm::dmat3 rotation{1.0};  ///< the rotation tool frame -> world it was built for (the cache key with cell_m)
    std::array<ToolDexelSet, 3> sets;  ///< X, Y, Z tool rays
    Vec3 lo_cells{0.0};      ///< bounds of the rotated tool relative to its reference point, workpiece cells
    Vec3 hi_cells{0.0};

    /// Number of intervals in all three sets.
    std::size_t interval_count() const;
};

/// The rotation that turns the tool frame into the world for tool axis `axis` (any non-zero length):
/// the shortest-arc rotation taking +z to axis/|axis| (Rodrigues about z x axis). For axis exactly -z (the
/// arc is not unique) it is the half turn about +x: (x, y, z) -> (x, -y, -z). There is no spin about the axis:
/// a tool that is not rotationally symmetric keeps the heading this convention gives it.
/// Throws tridex::Error when axis is not finite or is zero.
glm::dmat3 tool_rotation(const Vec3& axis);

/// The rotation matrix of the orientation `q` (tool frame -> world, any non-zero length: normalised here),
/// roll about the tool axis included. Throws tridex::Error when q is not finite or is zero.
glm::dmat3 tool_rotation(const Quat& q);

/// Any closed mesh as a tool. The mesh is given in the TOOL FRAME, metres: the origin is the
/// tool's reference point (the point that follows the path, Sweep::path_m), +z is the tool axis (it is
/// turned onto Sweep::axis by tool_rotation) unless the sweep carries its full orientation
/// (Sweep::orientation: the mesh is then in the frame of core/tool_shape.hpp, +y the tool axis, and is
/// turned by that rotation, roll included).
///
/// Method: per (orientation, workpiece cell size) the ROTATED mesh is scan-converted (scan_convert) into
/// world-axis-aligned tool dexels at lateral spacing h = cell/k (ToolDexels, built once, cached: the last
/// kCacheEntries orientations). A sweep applies the tool at poses spaced at most half a cell along the
/// segment (like the flat-end mill); at each pose the workpiece ray of set a at lateral position x
/// (relative to the pose) reads the tool ray of set a NEAREST to x (round(x*k), per axis) and applies each
/// of its intervals, shifted to the pose's depth, with subtract / union / paint (compute/tools/sweep.cpp).
///
/// Error bound: each applied chord is the exact tool's chord at a lateral position within h/2 = 0.5/k
/// cells per axis of the ray (scan conversion is exact at the tool rays), so the cut surface is within
/// sqrt(2)/(2k) cells of the exact surface measured laterally; plus the scallop between poses half a cell
/// apart (for a convex tool of radius of curvature rho cells: rho - sqrt(rho^2 - 1/16)); plus float
/// rounding. Per-ray DEPTH differences are larger where rays graze the tool (steep surface), up to the
/// tool's depth change over 0.5/k cells. Measured in tests/compute/test_mesh_tool_accuracy.cpp.
/// Thread-safe (the cache is guarded by a mutex); ToolDexels handed out stay valid while referenced.
class MeshTool {
public:
    static constexpr int kDefaultRaysPerCell = 4;  ///< k: tool rays per workpiece cell
    static constexpr std::size_t kCacheEntries = 8;
    static constexpr std::size_t kMaxToolBytes = std::size_t{1} << 30;  ///< tool tri-dexel build limit

    /// Checks and keeps `tool_m` (tool frame, m). k = tool rays per workpiece cell (1..16).
    /// Throws tridex::Error "mesh tool <name>: ..." when the mesh has no triangles, a non-finite position,
    /// an index out of range, degenerate triangles (repeated index or zero area), boundary edges (open),
    /// non-manifold or misoriented edges, or zero volume; a mesh with negative volume is flipped.
    static std::shared_ptr<const MeshTool> create(TriMesh tool_m, int k = kDefaultRaysPerCell, const std::string& name = "(mesh)");

    /// Loads a closed mesh file (compute::load_closed_mesh: precheck, OpenMesh, weld, closed/manifold
    /// checks), scales its coordinates by scale_m (file units -> m) and calls create(). Throws tridex::Error
    /// "<path>: ..." as load_closed_mesh does, or as create() does.
    static std::shared_ptr<const MeshTool> load(const std::string& path, double scale_m = 1.0, int k = kDefaultRaysPerCell);

    /// The tool's dexels for `axis` on a workpiece of cell size cell_m (m, > 0), built on first use and
    /// cached: dexels(tool_rotation(axis), cell_m). Cost of a build: O(triangles + tool rays + crossings)
    /// with (extent*k/cell)^2 rays per set. Throws tridex::Error when cell_m or axis is not usable, or the
    /// model would need over kMaxToolBytes.
    std::shared_ptr<const ToolDexels> dexels(const Vec3& axis, double cell_m) const;
    /// The tool's dexels with the mesh turned by `rotation` (tool frame -> world, a proper rotation: the full
    /// orientation, roll included), cached per (rotation, cell_m) exactly. Throws as above, and when the
    /// rotation is not finite.
    std::shared_ptr<const ToolDexels> dexels(const glm::dmat3& rotation, double cell_m) const;

    /// Bounds (m) of the tool turned onto `axis`, relative to the reference point (exact: rotated vertices).
    Aabb rotated_bounds(const Vec3& axis) const;
    /// Bounds (m) of the tool turned by `rotation` (tool frame -> world), relative to the reference point.
    Aabb rotated_bounds(const glm::dmat3& rotation) const;

    /// The checked mesh, tool frame, m.
    const TriMesh& mesh() const { return mesh_; }
    /// Largest distance of a vertex from the reference point, m.
    double bounding_radius_m() const { return radius_m_; }
    /// Tool rays per workpiece cell.
    int rays_per_cell() const { return k_; }

private:
    MeshTool() = default;
    TriMesh mesh_;
    int k_ = kDefaultRaysPerCell;
    double radius_m_ = 0.0;
    std::string name_;
    mutable std::mutex mutex_;
    mutable std::vector<std::shared_ptr<const ToolDexels>> cache_;  // most recent last
    mutable glm::dmat3 bounds_rotation_{0.0};
    mutable Aabb bounds_;
};

}  // namespace tridex::compute
