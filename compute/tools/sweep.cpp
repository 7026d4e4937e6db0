// compute/tools/sweep.cpp - swept-volume Booleans on the CPU (the reference for the GPU kernel).
#include "compute/tools/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "compute/tools/capsule.hpp"
#include "compute/model/interval_ops.hpp"
#include "core/error.hpp"

namespace tridex::compute {
namespace {

constexpr double kMaxGrid = 16777216.0;  // 2^24 cells: beyond this float depths lose whole cells

std::int32_t clamp_node(double g) { return static_cast<std::int32_t>(std::clamp(g, -2.0, kMaxGrid)); }

/// Poses at most half a cell apart from grid start ga to end gb: ceil(|gb - ga| / 0.5) + 1 (at most 10^7 + 1).
std::uint32_t half_cell_stamps(const Vec3& ga, const Vec3& gb) {
    const double n = std::ceil(glm::length(gb - ga) / 0.5);
    return static_cast<std::uint32_t>(std::min(n, 1.0e7)) + 1u;
}

/// Origin, start and delta of a GridSweep from the grid-unit motion ga -> gb.
void set_motion(GridSweep& g, const Vec3& ga, const Vec3& gb) {
    for (int k = 0; k < 3; ++k) {
        const double o = std::floor(ga[k]);
        g.origin[k] = static_cast<std::int32_t>(o);
        g.start[k] = static_cast<float>(ga[k] - o);
        g.delta[k] = static_cast<float>(gb[k] - ga[k]);
    }
}

/// to_grid_sweep for kMesh: the footprint is the rotated tool's box at both ends, widened by 1/k cell
/// (the nearest tool ray may lie up to 0.5/k cell beyond the exact bounds).
GridSweep to_grid_mesh_sweep(const Lattice& L, const Sweep& s, ToolTable* tools) {
    if (!s.tool.mesh) throw Error("sweep: a kMesh tool needs SweepTool::mesh");
    if (!s.orientation && (!is_finite(s.axis) || !(glm::length(s.axis) > 0.0)))
        throw Error("sweep: tool axis must be a finite, non-zero vector");
    const glm::dmat3 R = mesh_sweep_rotation(s);
    if (tools == nullptr) throw Error("sweep: a kMesh sweep needs a ToolTable (to_grid_batch, apply_sweep)");
    const Vec3 ga = L.to_grid(s.path_m.a), gb = L.to_grid(s.path_m.b);
    const Aabb box = sweep_bounds(s);
    const Vec3 glo = L.to_grid(box.lo), ghi = L.to_grid(box.hi);
    for (int k = 0; k < 3; ++k)
        if (std::fabs(glo[k]) > kMaxGrid || std::fabs(ghi[k]) > kMaxGrid)
            throw Error("sweep: the tool is more than 2^24 cells from the workpiece's lattice");
    const std::shared_ptr<const ToolDexels> dex = s.tool.mesh->dexels(R, L.cell_m);
    GridSweep g{};
    const double reach = 1.0 / dex->k;
    for (int k = 0; k < 3; ++k) {
        g.lo[k] = clamp_node(std::ceil(glo[k] - reach));
        g.hi[k] = clamp_node(std::floor(ghi[k] + reach));
        g.shank[k] = 0.0f;
    }
    set_motion(g, ga, gb);
    g.radius = static_cast<float>(s.tool.mesh->bounding_radius_m() / L.cell_m);
    g.stamps = half_cell_stamps(ga, gb);
    auto it = std::find(tools->begin(), tools->end(), dex);
    g.tool = static_cast<std::uint32_t>(it - tools->begin());
    if (it == tools->end()) tools->push_back(dex);
    g.code = static_cast<std::uint32_t>(s.op) | (static_cast<std::uint32_t>(s.tool.kind) << 8) |
             (static_cast<std::uint32_t>(s.material) << 16);
    return g;
}

}  // namespace

glm::dmat3 mesh_sweep_rotation(const Sweep& s) {
    if (s.orientation) {
        const Quat& q = *s.orientation;
        if (!std::isfinite(q.w) || !std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
            throw Error("sweep: tool orientation is not finite");
        return tool_rotation(q);
    }
    return tool_rotation(s.axis);
}

SweepTool sweep_tool(const ToolShape& shape, std::shared_ptr<const MeshTool> mesh) {
    if (shape.kind == ToolKind::kMesh && !mesh)
        throw Error("sweep_tool: a mesh tool (mesh_id " + std::to_string(shape.mesh_id) + ") needs its loaded mesh");
    return SweepTool{shape.kind, shape.radius_m, shape.kind == ToolKind::kFlatEnd ? shape.length_m : 0.0,
                     shape.kind == ToolKind::kMesh ? std::move(mesh) : nullptr};
}

Aabb sweep_bounds(const Sweep& s) {
    Aabb box;
    if (s.tool.kind == ToolKind::kMesh && s.tool.mesh) {
        const Aabb t = s.tool.mesh->rotated_bounds(mesh_sweep_rotation(s));
        box.add(s.path_m.a + t.lo);
        box.add(s.path_m.a + t.hi);
        box.add(s.path_m.b + t.lo);
        box.add(s.path_m.b + t.hi);
        return box;
    }
    box.add(s.path_m.a);
    box.add(s.path_m.b);
    if (s.tool.kind == ToolKind::kFlatEnd) {
        const Vec3 shank = glm::normalize(s.axis) * s.tool.length_m;
        box.add(s.path_m.a + shank);
        box.add(s.path_m.b + shank);
    }
    return box.inflated(s.tool.radius_m);
}

Aabb sweep_dirty_bounds(const Sweep& s, const Lattice& lattice) {
    const Aabb box = sweep_bounds(s);
    return s.tool.kind == ToolKind::kMesh ? box.inflated(0.5 * lattice.cell_m) : box;
}

GridSweep to_grid_sweep(const Lattice& L, const Sweep& s, ToolTable* tools) {
    if (!is_finite(s.path_m.a) || !is_finite(s.path_m.b)) throw Error("sweep: tool path (path_m) is not finite");
    if (s.tool.kind != ToolKind::kBall && s.tool.kind != ToolKind::kFlatEnd && s.tool.kind != ToolKind::kMesh)
        throw Error("sweep: unknown tool kind");
    const bool mesh = s.tool.kind == ToolKind::kMesh;
    if (mesh) return to_grid_mesh_sweep(L, s, tools);
    if (!std::isfinite(s.tool.radius_m) || !(s.tool.radius_m > 0.0))
        throw Error("sweep: tool radius_m must be a positive number of metres, got " + std::to_string(s.tool.radius_m));
    const bool flat = s.tool.kind == ToolKind::kFlatEnd;
    if (flat) {
        if (!std::isfinite(s.tool.length_m) || !(s.tool.length_m > 0.0))
            throw Error("sweep: flat-end tool length_m must be a positive number of metres, got " + std::to_string(s.tool.length_m));
        if (!is_finite(s.axis) || !(glm::length(s.axis) > 0.0)) throw Error("sweep: tool axis must be a finite, non-zero vector");
    }
    const Vec3 ga = L.to_grid(s.path_m.a), gb = L.to_grid(s.path_m.b);
    const Aabb box = sweep_bounds(s);
    const Vec3 glo = L.to_grid(box.lo), ghi = L.to_grid(box.hi);
    for (int k = 0; k < 3; ++k)
        if (std::fabs(glo[k]) > kMaxGrid || std::fabs(ghi[k]) > kMaxGrid)
            throw Error("sweep: the tool is more than 2^24 cells from the workpiece's lattice");
    GridSweep g{};
    const double r = s.tool.radius_m / L.cell_m;
    const Vec3 shank = flat ? glm::normalize(s.axis) * (s.tool.length_m / L.cell_m) : Vec3(0.0);
    for (int k = 0; k < 3; ++k) {
        g.lo[k] = clamp_node(std::ceil(glo[k]));
        g.hi[k] = clamp_node(std::floor(ghi[k]));
        g.shank[k] = static_cast<float>(shank[k]);
    }
    set_motion(g, ga, gb);
    g.radius = static_cast<float>(r);
    g.stamps = 1u;  // ball and flat end: one closed-form chord of the whole swept volume
    g.code = static_cast<std::uint32_t>(s.op) | (static_cast<std::uint32_t>(s.tool.kind) << 8) |
             (static_cast<std::uint32_t>(s.material) << 16);
    return g;
}

GridBatch to_grid_batch(const Lattice& lattice, std::span<const Sweep> batch) {
    GridBatch g;
    g.sweeps.reserve(batch.size());
    g.source.reserve(batch.size());
    for (std::size_t i = 0; i < batch.size(); ++i) {
        if (batch[i].op == ToolOp::kNone) continue;
        g.sweeps.push_back(to_grid_sweep(lattice, batch[i], &g.tools));
        g.source.push_back(i);
    }
    return g;
}

bool sweep_chord(const GridSweep& s, int axis, int u, int v, std::uint32_t /*stamp*/, float& d0, float& d1) {
    const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
    glm::vec3 o(0.0f), d(0.0f);
    d[axis] = 1.0f;
    o[ua] = static_cast<float>(u - s.origin[ua]) - s.start[ua];
    o[va] = static_cast<float>(v - s.origin[va]) - s.start[va];
    const glm::vec3 delta(s.delta[0], s.delta[1], s.delta[2]);
    float t0, t1;
    bool hit;
    if (s.kind() == ToolKind::kMesh) return false;  // mesh tools give several spans: mesh_stamp_spans
    if (s.kind() == ToolKind::kBall) {
        hit = capsule_chord(o, d, glm::vec3(0.0f), delta, s.radius, t0, t1);
    } else {
        hit = swept_cylinder_chord(o, d, glm::vec3(s.shank[0], s.shank[1], s.shank[2]), delta, s.radius, t0, t1);
    }
    if (!hit) return false;
    const float base = static_cast<float>(s.origin[axis]) + s.start[axis];
    d0 = base + t0;
    d1 = base + t1;
    return true;
}

std::size_t mesh_stamp_spans(const GridSweep& s, const ToolDexels& tool, int axis, int u, int v, std::uint32_t stamp,
                             std::vector<float>& spans) {
    const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
    const float f = s.stamps > 1 ? static_cast<float>(stamp) / static_cast<float>(s.stamps - 1) : 0.0f;
    const glm::vec3 c = glm::vec3(s.delta[0], s.delta[1], s.delta[2]) * f;
    const float ou = static_cast<float>(u - s.origin[ua]) - s.start[ua];
    const float ov = static_cast<float>(v - s.origin[va]) - s.start[va];
    const float kf = static_cast<float>(tool.k);
    const float xu = ou - c[ua], xv = ov - c[va];
    const float su = xu * kf, sv = xv * kf;
    const ToolDexelSet& set = tool.sets[axis];
    const float fu = std::floor(su + 0.5f), fv = std::floor(sv + 0.5f);
    // Compare in float first: far rays must not overflow the int conversion.
    if (!(fu >= static_cast<float>(-set.ref_u)) || !(fu < static_cast<float>(set.nu - set.ref_u))) return 0;
    if (!(fv >= static_cast<float>(-set.ref_v)) || !(fv < static_cast<float>(set.nv - set.ref_v))) return 0;
    const int iu = static_cast<int>(fu) + set.ref_u, iv = static_cast<int>(fv) + set.ref_v;
    const std::size_t ray = static_cast<std::size_t>(iu) + static_cast<std::size_t>(set.nu) * static_cast<std::size_t>(iv);
    const float base = static_cast<float>(s.origin[axis]) + s.start[axis];
    const float ca = c[axis];
    for (std::uint32_t q = set.first[ray]; q < set.first[ray + 1]; ++q) {
        const float p0 = ca + set.depth[2 * q], p1 = ca + set.depth[2 * q + 1];
        spans.push_back(base + p0);
        spans.push_back(base + p1);
    }
    return set.first[ray + 1] - set.first[ray];
}

SweepBallRays::SweepBallRays(const GridSweep& s, int axis)
    : capsule_(axis, glm::vec3(s.delta[0], s.delta[1], s.delta[2]), s.radius),
      origin_u_(s.origin[(axis + 1) % 3]),
      origin_v_(s.origin[(axis + 2) % 3]),
      start_u_(s.start[(axis + 1) % 3]),
      start_v_(s.start[(axis + 2) % 3]),
      base_(static_cast<float>(s.origin[axis]) + s.start[axis]) {}

bool apply_sweep_to_ray(const GridSweep& s, int axis, int u, int v, std::vector<Interval>& ray, float depth_cells,
                        std::span<const std::shared_ptr<const ToolDexels>> tools, const SweepBallRays* ball,
                        ChangedSpan* span) {
    const ToolOp op = s.op();
    if (op == ToolOp::kNone) return false;
    bool changed = false;
    if (s.kind() == ToolKind::kMesh) {
        if (s.tool >= tools.size() || !tools[s.tool]) throw Error("sweep: mesh tool index not in the batch's ToolTable");
        const ToolDexels& tool = *tools[s.tool];
        thread_local std::vector<float> spans;
        for (std::uint32_t k = 0; k < s.stamps; ++k) {
            spans.clear();
            mesh_stamp_spans(s, tool, axis, u, v, k, spans);
            for (std::size_t i = 0; i < spans.size(); i += 2) {
                const float d0 = spans[i], d1 = spans[i + 1];
                if (op == ToolOp::kSubtract)
                    changed |= subtract_interval_changed(ray, d0, d1, s.material(), span);
                else if (op == ToolOp::kUnion)
                    changed |=
                        union_interval_changed(ray, std::max(d0, 0.0f), std::min(d1, depth_cells), s.material(), span);
                else if (op == ToolOp::kPaint)
                    changed |= paint_interval_changed(ray, d0, d1, s.material(), span);
            }
        }
        return changed;
    }
    for (std::uint32_t k = 0; k < s.stamps; ++k) {
        float d0, d1;
        const bool hit = ball != nullptr && s.kind() == ToolKind::kBall ? ball->chord(u, v, d0, d1)
                                                                         : sweep_chord(s, axis, u, v, k, d0, d1);
        if (!hit) continue;
        if (op == ToolOp::kSubtract)
            changed |= subtract_interval_changed(ray, d0, d1, s.material(), span);
        else if (op == ToolOp::kUnion)
            changed |= union_interval_changed(ray, std::max(d0, 0.0f), std::min(d1, depth_cells), s.material(), span);
        else if (op == ToolOp::kPaint)
            changed |= paint_interval_changed(ray, d0, d1, s.material(), span);
    }
    return changed;
}

bool sweep_footprint(const GridSweep& s, const RaySet& set, int& u_lo, int& u_hi, int& v_lo, int& v_hi) {
    const int ua = (set.axis + 1) % 3, va = (set.axis + 2) % 3;
    u_lo = std::max(0, s.lo[ua]);
    u_hi = std::min(set.nu - 1, s.hi[ua]);
    v_lo = std::max(0, s.lo[va]);
    v_hi = std::min(set.nv - 1, s.hi[va]);
    return u_lo <= u_hi && v_lo <= v_hi;
}

SweepShadow::SweepShadow(const GridSweep& s, int axis) {
    const ToolKind kind = s.kind();
    if (kind != ToolKind::kBall && kind != ToolKind::kFlatEnd) return;
    const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
    const double du = s.delta[ua], dv = s.delta[va], R = s.radius;
    const double su = kind == ToolKind::kFlatEnd ? s.shank[ua] : 0.0, sv = kind == ToolKind::kFlatEnd ? s.shank[va] : 0.0;
    // The margin keeps the float rounding of the chords far inside.
    const double r = R + 1e-3 + 1e-5 * (R + std::fabs(du) + std::fabs(dv) + std::fabs(su) + std::fabs(sv));
    const double bu = static_cast<double>(s.origin[ua]) + s.start[ua], bv = static_cast<double>(s.origin[va]) + s.start[va];
    if (kind == ToolKind::kBall) {
        parts_[0] = CapsuleShadow(du, dv, r, bu, bv);
        count_ = 1;
        return;
    }
    // The flat end lies within the capsule around its axis, so its swept volume's shadow lies within the
    // parallelogram of the projected shank and motion widened by r: the hull of the capsules around its four edges.
    parts_[0] = CapsuleShadow(su, sv, r, bu, bv);
    parts_[1] = CapsuleShadow(su, sv, r, bu + du, bv + dv);
    parts_[2] = CapsuleShadow(du, dv, r, bu, bv);
    parts_[3] = CapsuleShadow(du, dv, r, bu + su, bv + sv);
    count_ = 4;
}

bool SweepShadow::row(int v, int& u_lo, int& u_hi) const {
    if (count_ == 0) return u_lo <= u_hi;
    double lo = INFINITY, hi = -INFINITY;  // the hull of the parts' sections (the shadow is convex)
    for (int k = 0; k < count_; ++k) {
        double a, b;
        if (!parts_[k].section(v, a, b)) continue;
        lo = std::min(lo, a);
        hi = std::max(hi, b);
    }
    return shadow_nodes(lo, hi, u_lo, u_hi);
}

bool SweepShadow::band(int v_first, int v_last, int& u_lo, int& u_hi) const {
    int lo = INT32_MAX, hi = INT32_MIN;
    for (int v = v_first; v <= v_last; ++v) {
        int a = u_lo, b = u_hi;
        if (!row(v, a, b)) continue;
        lo = std::min(lo, a);
        hi = std::max(hi, b);
    }
    if (lo > hi) return false;
    u_lo = lo;
    u_hi = hi;
    return true;
}

BooleanStats apply_sweep(TriDexel& model, const Sweep& sweep) {
    BooleanStats stats;
    if (sweep.op == ToolOp::kNone) return stats;
    ToolTable tools;
    const GridSweep g = to_grid_sweep(model.lattice, sweep, &tools);
    ChangedBox changed;  // the changed interval ends: what the contour must redo around
    for (int ax = 0; ax < 3; ++ax) {
        RaySet& set = model.sets[ax];
        int u_lo, u_hi, v_lo, v_hi;
        if (!sweep_footprint(g, set, u_lo, u_hi, v_lo, v_hi)) continue;
        const SweepBallRays ball(g, ax);
        const SweepShadow shadow(g, ax);
        for (int v = v_lo; v <= v_hi; ++v) {
            stats.rays_visited += static_cast<std::size_t>(u_hi - u_lo + 1);
            int a = u_lo, b = u_hi;
            if (!shadow.row(v, a, b)) continue;  // rays the swept volume cannot reach keep their intervals
            for (int u = a; u <= b; ++u) {
                ChangedSpan span;
                if (apply_sweep_to_ray(g, ax, u, v, set.ray(u, v), static_cast<float>(model.lattice.cells[ax]), tools,
                                       &ball, &span)) {
                    ++stats.rays_changed;
                    changed.add_ray(ax, u, v, span);
                }
            }
        }
    }
    changed.mark(model);
    return stats;
}

}  // namespace tridex::compute
