// compute/tools/clay_sweep.hpp - the clay operations (ToolOp::kPush, kSmooth, kPull, kGrab) as sweeps: validation,
// the box they may change, and applying one to a tri-dexel model (the CPU reference).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "compute/model/tridexel.hpp"
#include "compute/tools/clay_field.hpp"
#include "compute/tools/clay_kernel.hpp"
#include "compute/tools/sweep.hpp"
#include "core/aabb.hpp"
#include "core/tool_sample.hpp"

namespace tridex::compute {

/// True for the operations that move material instead of adding or removing a swept volume (kPush, kSmooth, kPull,
/// kGrab).
inline bool is_clay_op(ToolOp op) {
    return op == ToolOp::kPush || op == ToolOp::kSmooth || op == ToolOp::kPull || op == ToolOp::kGrab;
}

/// True for the clay operations whose short consecutive sweeps apply_clay_batch applies as one group (kPush, kSmooth,
/// kGrab), so that SculptHistory holds an open group of them back at the end of a batch.
inline bool is_grouped_clay_op(ToolOp op) {
    return op == ToolOp::kPush || op == ToolOp::kSmooth || op == ToolOp::kGrab;
}

/// How far (cells) beyond its ball radius R a clay sweep's tool may change the model: push and pull R*(kClayInfluence*(1 +
/// kClayRimWidth)) plus the contact's distance (at most R), smooth R*kClayInfluence plus the contact's distance, grab
/// R*kClayGrabInfluence plus the contact's distance, one grab step and the 2 cells its field looks back.
float clay_reach_cells(ToolOp op, float radius_cells);

/// A clay sweep in grid units: the ball of radius sweep.tool.radius_m (kFlatEnd: its radius; kMesh: the mesh's
/// bounding radius), origin/start/delta as to_grid_sweep, stamps at most half a cell apart (push, pull) or 1 (smooth),
/// lo..hi the node box it may change (clay_reach_cells and kClayMarginCells beyond the motion), clamped to the
/// lattice. Throws tridex::Error as to_grid_sweep on bad input, and when op is not a clay op.
GridSweep to_clay_grid_sweep(const Lattice& lattice, const Sweep& sweep);

/// World box (m) a clay sweep may change: its node box lo..hi (not clamped) on `lattice`. Empty when the sweep is
/// not finite (the clay ops refuse it).
Aabb clay_bounds(const Lattice& lattice, const Sweep& sweep);

/// Longest motion (cells) one push is applied over at once; a longer one is applied as that many equal pieces in
/// order (apply_clay).
inline constexpr double kClayPieceCells = 2.0;

/// Applies one clay sweep (clay_push, clay_pull, clay_smooth or clay_grab) to `model`; a push, pull or grab moving
/// more than kClayPieceCells goes in equal pieces of at most that, in order. Appends the changed rays' old images to
/// `before` when not null (a ray changed by two pieces is listed twice; its first image is the one before the
/// sweep). Throws tridex::Error (model unchanged) on the input to_clay_grid_sweep refuses. The per-node and per-ray
/// work runs on `kernel` (the CPU reference by default, or the GPU's compute/gpu/gpu_clay.hpp: the same model and
/// ClayStats bit for bit); a kernel's device failure is thrown as tridex::Error after the pieces before it were
/// written.
ClayStats apply_clay(TriDexel& model, const Sweep& sweep, std::vector<RayImage>* before = nullptr,
                     ClayKernel& kernel = clay_cpu_kernel());

/// Group extent per cell of ball radius (clay_group_cells).
inline constexpr float kClayGroupReach = 2.0f;
/// Shortest group extent, cells: a small tool's operation costs mostly its fixed part, so its groups may run longer.
inline constexpr float kClayGroupMinCells = 12.0f;
/// Longest extent (cells) of the tool centres' motion that apply_clay_batch applies as one push or smooth, for a ball of
/// radius R cells: the larger of kClayGroupMinCells and kClayGroupReach * R. An operation's cost grows with the cube
/// of its region's radius, about (r + w) plus half the extent, so a group about as long as that radius costs the
/// least per sweep.
float clay_group_cells(float radius_cells);
/// Most sweeps apply_clay_batch puts in one push or smooth group unless told otherwise (the group_sweeps argument);
/// a session records the size it used (app::SessionSpec::clay_group_sweeps), since the grouping decides the model. A
/// session makes a sweep per haptic tick, so this bounds how long a held group waits for its last sweep
/// (SculptHistory) to this many ticks, however slowly the tool moves.
inline constexpr std::size_t kClayGroupSweeps = 32;
/// Most sweeps a group may be given (group_sweeps): longer groups only make a slow stroke's held group wait longer.
inline constexpr std::size_t kClayGroupSweepsMax = 256;

/// Throws tridex::Error "clay group size: ..." unless 1 <= group_sweeps <= kClayGroupSweepsMax.
void check_clay_group_sweeps(std::size_t group_sweeps);

/// Applies a batch of sweeps in order: Boolean sweeps with apply_sweep, clay sweeps with apply_clay, except that
/// runs of at most group_sweeps consecutive push sweeps (or smooth sweeps) of one tool, each moving at most
/// kClayPieceCells, whose motion spans at most clay_group_cells(R) together, go as one clay_push_group (or
/// clay_smooth_group), and runs of at most group_sweeps consecutive grab sweeps of one tool that join end to end
/// (each starting where the one before it ended) and span at most kClayPieceCells together go as one grab from the
/// first one's start to the last one's end (apply_clay). The grouping depends only on the sweeps, so the same
/// batch gives the same model bit for bit (a session journal records its batches). Validates the whole batch first
/// (tridex::Error, model unchanged). Appends old ray images to `before` (clay sweeps only) when not null; returns
/// the summed ray counts. Clay work runs on `kernel`; Booleans on the CPU (callers with a faster Boolean path split
/// the batch and call this for the clay runs).
/// Throws tridex::Error as check_clay_group_sweeps for a bad group_sweeps.
BooleanStats apply_clay_batch(TriDexel& model, std::span<const Sweep> batch, std::vector<RayImage>* before = nullptr,
                              ClayKernel& kernel = clay_cpu_kernel(), std::size_t group_sweeps = kClayGroupSweeps);

/// Where the last group of `batch` starts, when apply_clay_batch would end the batch with a push, smooth or grab group
/// that later sweeps of the same stroke could still join (its last sweep a groupable push, smooth or grab): the index
/// of that group's first sweep; batch.size() when the batch ends with anything else. Grouping is greedy from the start of each run of clay
/// sweeps, so applying batch[0, k) now and batch[k, n) with whatever follows gives the same groups, and the same
/// model, however a stroke's sweeps are split into batches (SculptHistory holds that open group back). Throws
/// tridex::Error as to_clay_grid_sweep on a bad clay sweep in the trailing run, and as check_clay_group_sweeps.
/// `group_sweeps` must be the one the batch is applied with.
std::size_t clay_open_group(const Lattice& lattice, std::span<const Sweep> batch,
                            std::size_t group_sweeps = kClayGroupSweeps);

}  // namespace tridex::compute
