// compute/tools/clay_sweep.cpp - clay sweeps: grid form, bounds, and the CPU reference dispatch.
#include "compute/tools/clay_sweep.hpp"

#include <algorithm>
#include <cmath>

#include "compute/tools/clay_grab.hpp"
#include "compute/tools/clay_push.hpp"
#include "compute/tools/clay_smooth.hpp"
#include "core/error.hpp"

namespace tridex::compute {
namespace {

double ball_radius_m(const Sweep& s) {
    if (s.tool.kind == ToolKind::kMesh) {
        if (!s.tool.mesh) throw Error("sweep: a kMesh tool needs SweepTool::mesh");
        return s.tool.mesh->bounding_radius_m();
    }
    return s.tool.radius_m;
}

}  // namespace

float clay_reach_cells(ToolOp op, float radius_cells) {
    const float r = kClayInfluence * radius_cells;
    // The contact point lies at most R from the centre while in contact (phi <= R + 0.5).
    const float contact = radius_cells + 0.5f;
    if (op == ToolOp::kGrab) return contact + kClayGrabInfluence * radius_cells + kClayGrabStepCells + 2.0f;
    return op != ToolOp::kSmooth ? contact + r * (1.0f + kClayRimWidth) : contact + r;
}

GridSweep to_clay_grid_sweep(const Lattice& L, const Sweep& s) {
    if (!is_clay_op(s.op)) throw Error("clay sweep: the operation is not push, smooth, pull or grab");
    Sweep ball = s;
    ball.tool.kind = ToolKind::kBall;
    ball.tool.radius_m = ball_radius_m(s);
    ball.tool.length_m = 0.0;
    ball.tool.mesh = nullptr;
    GridSweep g = to_grid_sweep(L, ball);  // validates like a ball Boolean; origin, start, delta, radius
    const float reach = clay_reach_cells(s.op, g.radius);
    for (int a = 0; a < 3; ++a) {
        const float s0 = g.start[a], s1 = g.start[a] + g.delta[a];
        const double lo = std::floor(static_cast<double>(g.origin[a]) + std::min(s0, s1) - reach) - kClayMarginCells;
        const double hi = std::ceil(static_cast<double>(g.origin[a]) + std::max(s0, s1) + reach) + kClayMarginCells;
        g.lo[a] = static_cast<std::int32_t>(std::clamp(lo, 0.0, static_cast<double>(L.cells[a])));
        g.hi[a] = static_cast<std::int32_t>(std::clamp(hi, 0.0, static_cast<double>(L.cells[a])));
        if (hi < 0.0 || lo > L.cells[a]) g.hi[a] = g.lo[a] - 1;  // off the lattice: an empty box
    }
    if (s.op != ToolOp::kSmooth) {
        const float len = std::sqrt(g.delta[0] * g.delta[0] + g.delta[1] * g.delta[1] + g.delta[2] * g.delta[2]);
        g.stamps = static_cast<std::uint32_t>(std::min(std::ceil(len / 0.5f), 1.0e6f));
        g.stamps = std::max<std::uint32_t>(g.stamps, 1u);
    } else {
        g.stamps = 1;
    }
    return g;
}

Aabb clay_bounds(const Lattice& L, const Sweep& s) {
    Aabb box;
    if (!is_finite(s.path_m.a) || !is_finite(s.path_m.b) || !(L.cell_m > 0.0)) return box;
    double R = 0.0;
    try {
        R = ball_radius_m(s);
    } catch (const Error&) {
        return box;
    }
    if (!std::isfinite(R) || !(R > 0.0)) return box;
    const double reach =
        static_cast<double>(clay_reach_cells(s.op, static_cast<float>(R / L.cell_m))) + kClayMarginCells + 1.0;
    box.add(s.path_m.a);
    box.add(s.path_m.b);
    return box.inflated(reach * L.cell_m);
}

ClayStats apply_clay(TriDexel& model, const Sweep& s, std::vector<RayImage>* before, ClayKernel& kernel) {
    const GridSweep g = to_clay_grid_sweep(model.lattice, s);  // validates the whole sweep first
    if (g.hi[0] < g.lo[0] || g.hi[1] < g.lo[1] || g.hi[2] < g.lo[2]) return {};
    if (s.op == ToolOp::kSmooth) return clay_smooth(model, g, before, kernel);
    // One piece of a push, pull or grab.
    const auto one = [&](const GridSweep& pg) {
        if (s.op == ToolOp::kGrab) return clay_grab(model, pg, before, kernel);
        return s.op == ToolOp::kPull ? clay_pull(model, pg, before, kernel) : clay_push(model, pg, before, kernel);
    };
    // A long push or pull (a jump of the workspace, a fast hand) in pieces of at most kClayPieceCells of motion, each with
    // its own field box around its contacts, so the cost follows the path's length, not the volume of its box.
    const double len = glm::length(s.path_m.b - s.path_m.a) / model.lattice.cell_m;
    const int pieces = static_cast<int>(std::min(std::ceil(len / kClayPieceCells), 1.0e6));
    if (pieces <= 1) return one(g);
    ClayStats total;
    for (int k = 0; k < pieces; ++k) {
        Sweep piece = s;
        piece.path_m.a = s.path_m.a + (s.path_m.b - s.path_m.a) * (static_cast<double>(k) / pieces);
        piece.path_m.b = s.path_m.a + (s.path_m.b - s.path_m.a) * (static_cast<double>(k + 1) / pieces);
        const GridSweep pg = to_clay_grid_sweep(model.lattice, piece);
        if (pg.hi[0] < pg.lo[0] || pg.hi[1] < pg.lo[1] || pg.hi[2] < pg.lo[2]) continue;
        const ClayStats st = one(pg);
        total.rays.rays_visited += st.rays.rays_visited;
        total.rays.rays_changed += st.rays.rays_changed;
        total.volume_change_cells += st.volume_change_cells;
        total.max_displacement_cells = std::max(total.max_displacement_cells, st.max_displacement_cells);
        total.beta = st.beta;
    }
    return total;
}

float clay_group_cells(float radius_cells) {
    return std::max(kClayGroupMinCells, kClayGroupReach * radius_cells);
}

namespace {

bool same_tool(const SweepTool& a, const SweepTool& b) {
    return a.kind == b.kind && a.radius_m == b.radius_m && a.length_m == b.length_m && a.mesh == b.mesh;
}

// True when push, smooth or grab sweep s may join a group: it moves at most kClayPieceCells and its box lies on the
// lattice.
bool groupable(const Lattice& L, const Sweep& s, const GridSweep& g) {
    if (!is_grouped_clay_op(s.op)) return false;
    if (g.hi[0] < g.lo[0] || g.hi[1] < g.lo[1] || g.hi[2] < g.lo[2]) return false;
    return glm::length(s.path_m.b - s.path_m.a) / L.cell_m <= kClayPieceCells;
}

// One past the last sweep of the group apply_clay_batch starts at batch[i] (i + 1 for a sweep that goes alone), with
// groups of at most max_sweeps.
std::size_t clay_group_end(const Lattice& L, std::span<const Sweep> batch, std::span<const GridSweep> grid,
                           std::size_t i, std::size_t max_sweeps) {
    const Sweep& s = batch[i];
    if (!groupable(L, s, grid[i])) return i + 1;
    // The run of at most max_sweeps sweeps of this operation and tool whose centres' motion stays within
    // clay_group_cells of R; a grab's run, applied as one straight motion, within kClayPieceCells and end to end.
    const bool grab = s.op == ToolOp::kGrab;
    const double limit = grab ? kClayPieceCells : clay_group_cells(grid[i].radius);
    Vec3 lo = glm::min(s.path_m.a, s.path_m.b), hi = glm::max(s.path_m.a, s.path_m.b);
    std::size_t j = i + 1;
    while (j < batch.size() && j - i < max_sweeps && batch[j].op == s.op && same_tool(batch[j].tool, s.tool) &&
           groupable(L, batch[j], grid[j]) && (!grab || batch[j].path_m.a == batch[j - 1].path_m.b)) {
        const Vec3 nlo = glm::min(lo, glm::min(batch[j].path_m.a, batch[j].path_m.b));
        const Vec3 nhi = glm::max(hi, glm::max(batch[j].path_m.a, batch[j].path_m.b));
        if (glm::length(nhi - nlo) / L.cell_m > limit) break;
        lo = nlo, hi = nhi;
        ++j;
    }
    return j;
}

// The clay sweeps of a batch in grid form, other slots left default; every sweep validated (to_clay_grid_sweep or
// to_grid_sweep), so a bad one throws before anything changes.
std::vector<GridSweep> clay_batch_grid(const Lattice& L, std::span<const Sweep> batch) {
    std::vector<GridSweep> grid(batch.size());
    ToolTable tools;
    for (std::size_t i = 0; i < batch.size(); ++i)
        if (is_clay_op(batch[i].op))
            grid[i] = to_clay_grid_sweep(L, batch[i]);
        else if (batch[i].op != ToolOp::kNone)
            to_grid_sweep(L, batch[i], &tools);
    return grid;
}

}  // namespace

void check_clay_group_sweeps(std::size_t group_sweeps) {
    if (group_sweeps < 1 || group_sweeps > kClayGroupSweepsMax)
        throw Error("clay group size: must be 1.." + std::to_string(kClayGroupSweepsMax) + " sweeps, got " +
                    std::to_string(group_sweeps));
}

std::size_t clay_open_group(const Lattice& L, std::span<const Sweep> batch, std::size_t group_sweeps) {
    check_clay_group_sweeps(group_sweeps);
    if (batch.empty() || !is_grouped_clay_op(batch.back().op)) return batch.size();
    // The trailing run of clay sweeps (a Boolean before it closes every group), grouped from its start.
    std::size_t first = batch.size();
    while (first > 0 && is_clay_op(batch[first - 1].op)) --first;
    const std::span<const Sweep> run = batch.subspan(first);
    const std::vector<GridSweep> grid = clay_batch_grid(L, run);
    if (!groupable(L, run.back(), grid.back())) return batch.size();
    std::size_t i = 0;
    for (;;) {
        const std::size_t j = clay_group_end(L, run, grid, i, group_sweeps);
        if (j == run.size()) return first + i;
        i = j;
    }
}

BooleanStats apply_clay_batch(TriDexel& model, std::span<const Sweep> batch, std::vector<RayImage>* before,
                              ClayKernel& kernel, std::size_t group_sweeps) {
    check_clay_group_sweeps(group_sweeps);
    const Lattice& L = model.lattice;
    const std::vector<GridSweep> grid = clay_batch_grid(L, batch);  // validates the whole batch first
    BooleanStats total;
    const auto add = [&](const BooleanStats& b) {
        total.rays_visited += b.rays_visited;
        total.rays_changed += b.rays_changed;
    };
    std::size_t i = 0;
    while (i < batch.size()) {
        const Sweep& s = batch[i];
        if (!is_clay_op(s.op)) {
            add(apply_sweep(model, s));
            ++i;
            continue;
        }
        if (!groupable(L, s, grid[i])) {
            add(apply_clay(model, s, before, kernel).rays);
            ++i;
            continue;
        }
        const std::size_t j = clay_group_end(L, batch, grid, i, group_sweeps);
        if (s.op == ToolOp::kGrab) {  // one straight motion from the run's start to its end
            Sweep whole = s;
            whole.path_m.b = batch[j - 1].path_m.b;
            add(apply_clay(model, whole, before, kernel).rays);
            i = j;
            continue;
        }
        const std::span<const GridSweep> group = std::span<const GridSweep>(grid).subspan(i, j - i);
        add((s.op == ToolOp::kSmooth ? clay_smooth_group(model, group, before, kernel)
                                     : clay_push_group(model, group, before, kernel))
                .rays);
        i = j;
    }
    return total;
}

}  // namespace tridex::compute
