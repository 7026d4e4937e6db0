// compute/tools/sweep.hpp - one swept-volume Boolean (tool, motion, operation) and its CPU reference.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "compute/model/interval_ops.hpp"
#include "compute/model/tridexel.hpp"
#include "compute/tools/boolean.hpp"
#include "compute/tools/capsule.hpp"
#include "compute/tools/mesh_tool.hpp"
#include "core/segment.hpp"
#include "core/tool_sample.hpp"
#include "core/tool_shape.hpp"

namespace tridex::compute {

using tridex::ToolKind;  // the tool kinds are core vocabulary (core/tool_shape.hpp)

/// The tool of one sweep: a core ToolShape's kind and sizes, with a kMesh tool's loaded mesh (the core type
/// names it by index into a session's table; a sweep carries the mesh itself). Tool frame as ToolShape's,
/// except that a kMesh tool's frame +z is turned onto Sweep::axis (compute/tools/mesh_tool.hpp) unless the sweep
/// carries its full orientation (Sweep::orientation: then ToolShape's frame, turned by it).
struct SweepTool {
    ToolKind kind = ToolKind::kBall;
    double radius_m = 0.0;  ///< ball or cylinder radius, m (> 0); ignored for kMesh
    double length_m = 0.0;  ///< kFlatEnd: cylinder length along the axis, m (> 0); ignored otherwise
    std::shared_ptr<const MeshTool> mesh{};  ///< kMesh: the tool (tool frame +z turned onto Sweep::axis); else unused
};

/// The SweepTool of a core ToolShape: its kind and sizes, and for kMesh `mesh` (which must then be set).
SweepTool sweep_tool(const ToolShape& shape, std::shared_ptr<const MeshTool> mesh = {});

/// The mesh tools' dexels a batch of GridSweeps refers to (GridSweep::tool indexes it).
using ToolTable = std::vector<std::shared_ptr<const ToolDexels>>;

/// One swept Boolean: the tool moved in a straight line from path_m.a to path_m.b (world m) with a fixed
/// axis (world vector, normalised on use; the tool frame's +z; used by kFlatEnd and kMesh), applying `op` to the swept volume.
/// kMesh with `orientation` set: the mesh is turned by that full rotation (tool frame -> world, roll included;
/// a session's ToolSample::orientation, whose tool axis is +y) and `axis` is not used.
/// kSubtract removes it (new surface gets `material`), kUnion adds it as `material`, kPaint sets
/// `material` on the surface points inside it. kNone does nothing.
struct Sweep {
    ToolOp op = ToolOp::kSubtract;
    SweepTool tool{};
    Segment path_m{};
    Vec3 axis{0.0, 0.0, 1.0};
    std::uint8_t material = 0;
    std::optional<Quat> orientation{};  ///< kMesh: full tool orientation (unit quaternion); unset = tool_rotation(axis)
};

/// The rotation (tool frame -> world) a kMesh sweep turns its mesh by: tool_rotation(*orientation) when set,
/// else tool_rotation(axis). Throws tridex::Error when the one used is not finite or zero.
glm::dmat3 mesh_sweep_rotation(const Sweep& sweep);

/// A Sweep in grid units, the exact record the GPU kernel reads (std430, 96 bytes); the CPU reference
/// reads the same fields, so both compute the same float chords. Tool coordinates are relative to
/// the tool start A = origin + start (origin = floor(A), integer; start = A - origin, float), so
/// float precision does not depend on where the workpiece sits or on the lattice size.
struct GridSweep {
    std::int32_t lo[3];      ///< first lattice node index inside the swept box, per axis (may be < 0)
    std::uint32_t code;      ///< op | kind << 8 | material << 16
    std::int32_t hi[3];      ///< last lattice node index inside the swept box, per axis (may be >= nodes)
    std::uint32_t stamps;    ///< kMesh: tool poses applied along the motion (spacing <= 0.5 cell); kBall, kFlatEnd: 1
    std::int32_t origin[3];  ///< integer part of the tool start, grid units
    float radius;            ///< tool radius, grid units (kMesh: bounding radius, informative only)
    float start[3];          ///< fractional part of the tool start, grid units, in [0, 1)
    std::uint32_t tool;      ///< kMesh: index of the tool's dexels in the batch's ToolTable; else 0
    float delta[3];          ///< motion B - A, grid units
    float pad1;
    float shank[3];          ///< kFlatEnd: axis * length, grid units (the cylinder runs from a pose to pose + shank); else 0
    float pad2;

    ToolOp op() const { return static_cast<ToolOp>(code & 0xffu); }
    ToolKind kind() const { return static_cast<ToolKind>((code >> 8) & 0xffu); }
    std::uint8_t material() const { return static_cast<std::uint8_t>((code >> 16) & 0xffu); }
};
static_assert(sizeof(GridSweep) == 96, "GridSweep must match the std430 layout of shaders/dexel_sweep.comp");

/// A batch of sweeps in grid units: the sweeps whose op is not kNone, in batch order, and for each its
/// index in the batch; `tools` holds the distinct mesh-tool dexels the kMesh sweeps index (GridSweep::tool).
struct GridBatch {
    std::vector<GridSweep> sweeps;
    std::vector<std::size_t> source;
    ToolTable tools;
};

/// Converts every sweep of `batch` (skipping kNone) with to_grid_sweep, so a caller can validate a whole
/// batch before changing anything. Throws tridex::Error as to_grid_sweep on the first bad sweep.
GridBatch to_grid_batch(const Lattice& lattice, std::span<const Sweep> batch);

/// World bounding box of the swept volume (m): both end poses of the tool inflated by its radius (kMesh:
/// the rotated mesh's exact bounds at both end poses; the rays it changes may lie up to 0.5/k cell beyond
/// them, see sweep_dirty_bounds).
Aabb sweep_bounds(const Sweep& sweep);

/// The box (m) to pass to TriDexel::mark_dirty after applying `sweep` on `lattice`: sweep_bounds, and for
/// kMesh widened by half a cell, the nearest-ray reach of its stamps beyond the mesh's bounds (a partial
/// re-contour redoes only the cells near this box, so it must hold every changed ray).
Aabb sweep_dirty_bounds(const Sweep& sweep, const Lattice& lattice);

/// Converts a Sweep to grid units on `lattice`. Throws tridex::Error naming the field when a position or
/// the axis is not finite, the axis is zero, the radius (or kFlatEnd length) is not a positive number of
/// metres, the swept box is more than 2^24 cells from the lattice (float depths would lose cells), or a
/// kMesh sweep has no SweepTool::mesh. kMesh: the tool's dexels for (axis, cell size) are appended to
/// `tools` (once per distinct ToolDexels) and GridSweep::tool indexes them; throws when `tools` is null.
GridSweep to_grid_sweep(const Lattice& lattice, const Sweep& sweep, ToolTable* tools = nullptr);

/// Depth range [d0, d1] (grid units along set `axis`) that stamp `stamp` (0..stamps-1) of the sweep
/// covers on the ray of that set at lattice node (u, v); false when the ray misses it. The ray's line
/// relative to the tool start is o + t*e_axis with o[axis] = 0, o[k] = float(node_k - origin_k) - start_k
/// for the two other axes; depth = (float(origin[axis]) + start[axis]) + t. Ball: capsule_chord with the
/// segment 0 -> delta. kFlatEnd: swept_cylinder_chord of the cylinder with shank `shank` moved by delta
/// (the whole swept volume in closed form; `stamp` is unused for both). kMesh: always false (mesh_stamp_spans).
bool sweep_chord(const GridSweep& sweep, int axis, int u, int v, std::uint32_t stamp, float& d0, float& d1);

/// kMesh: the tool intervals that stamp `stamp` puts on the ray of set `axis` at node (u, v), appended to
/// `spans` as depth pairs (grid units). The pose is c = delta * (float(stamp) / float(stamps - 1)) (c = 0
/// when stamps == 1) relative to the tool start; with the ray's lateral offsets o (as in sweep_chord),
/// x_u = o[ua] - c[ua], the tool ray is i = int(floor(x_u * float(k) + 0.5f)) + ref_u (same for v), none
/// when outside the tool's grid; each tool interval [z0, z1] gives [base + (c[axis] + z0),
/// base + (c[axis] + z1)] with base = float(origin[axis]) + start[axis]. Float only, in this order (the
/// GPU kernel repeats it). Returns the number of spans appended.
std::size_t mesh_stamp_spans(const GridSweep& sweep, const ToolDexels& tool, int axis, int u, int v, std::uint32_t stamp,
                             std::vector<float>& spans);

/// A kBall sweep's chords on the rays of one set with everything that does not depend on the ray computed once
/// (AxisCapsule with e = delta, r = radius, and the offsets of sweep_chord): chord(u, v) gives sweep_chord's d0, d1
/// (grid units along the set) for the ray at node (u, v), bit for bit up to the sign of a zero. Default: no ray hits.
class SweepBallRays {
public:
    SweepBallRays() = default;
    SweepBallRays(const GridSweep& sweep, int axis);
    bool chord(int u, int v, float& d0, float& d1) const {
        const float ou = static_cast<float>(u - origin_u_) - start_u_;
        const float ov = static_cast<float>(v - origin_v_) - start_v_;
        float t0, t1;
        if (!capsule_.chord(ou, ov, t0, t1)) return false;
        d0 = base_ + t0;
        d1 = base_ + t1;
        return true;
    }

private:
    AxisCapsule capsule_;
    int origin_u_ = 0, origin_v_ = 0;
    float start_u_ = 0.0f, start_v_ = 0.0f, base_ = 0.0f;
};

/// Applies the sweep to one ray (set `axis`, node (u, v)): for each stamp, its chord (kMesh: each of its
/// spans, mesh_stamp_spans, in depth order) is subtracted, added or painted (interval_ops.hpp). A union
/// chord is first clipped to the lattice's depth range [0, depth_cells] (depth_cells = the lattice's cells
/// along `axis`), so no material is added where the lattice, the contour and the renderer cannot see it.
/// `tools` is the batch's ToolTable (needed for kMesh; throws tridex::Error when the index is not in it).
/// Returns true when the ray changed.
/// `ball` (optional, kBall only): the sweep's SweepBallRays for this set, which gives the same chords as
/// sweep_chord with less work per ray. `span` (optional): grown to hold every interval end the sweep
/// changed on this ray (ChangedSpan, grid units along it).
bool apply_sweep_to_ray(const GridSweep& sweep, int axis, int u, int v, std::vector<Interval>& ray, float depth_cells,
                        std::span<const std::shared_ptr<const ToolDexels>> tools = {},
                        const SweepBallRays* ball = nullptr, ChangedSpan* span = nullptr);

/// CPU reference of a swept Boolean on the whole model: applies the sweep to every ray of all three sets
/// whose node lies inside the swept box (GridSweep lo..hi) and to no other ray, and marks dirty the cells
/// around the interval ends it changed (ChangedBox, TriDexel::mark_dirty_grid). Cost: O(footprint rays x stamps x intervals per ray).
/// Throws tridex::Error (model unchanged) on the bad input to_grid_sweep rejects.
/// Source: Peng et al., tri-dexel Booleans with the tool's swept volume.
BooleanStats apply_sweep(TriDexel& model, const Sweep& sweep);

/// The shadow of a ball or flat-end sweep's swept volume on the rays of one set, row by row: row() narrows
/// [u_lo, u_hi] (nodes of one row of the footprint, node v along the set's second lateral axis) to the row's section
/// of the shadow, computed in double and widened by a margin far beyond the float rounding of the chords, so no ray
/// whose chord is non-empty is left out and the sweep's result is unchanged. Ball: the 2D capsule of radius R around
/// the motion 0 -> delta projected along the set's axis (exact). Flat end: the projected parallelogram of shank and
/// motion widened by R (it holds the swept cylinder's projection, since the cylinder lies within the capsule around
/// its axis). Returns false when the row misses. Mesh tools keep the range (row() returns u_lo <= u_hi).
class SweepShadow {
public:
    SweepShadow(const GridSweep& sweep, int axis);
    bool row(int v, int& u_lo, int& u_hi) const;
    /// The union of row() over the rows v_first..v_last: [u_lo, u_hi] narrowed to the nodes some of those rows
    /// reach; false when none does.
    bool band(int v_first, int v_last, int& u_lo, int& u_hi) const;

private:
    CapsuleShadow parts_[4];  // the shadow is the hull of their rows
    int count_ = 0;           // 0: no shadow known (mesh tools)
};

/// Footprint of a sweep on ray set `axis`: the node range [u_lo, u_hi] x [v_lo, v_hi] clamped to the
/// set; false when it is empty.
bool sweep_footprint(const GridSweep& sweep, const RaySet& set, int& u_lo, int& u_hi, int& v_lo, int& v_hi);

}  // namespace tridex::compute
