// app/scene/study_walls.cpp - the felt objects of a study model scan-converted by swept Booleans.
#include "app/scene/study_walls.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "app/support/memory.hpp"
#include "compute/model/volume.hpp"
#include "compute/tools/sweep.hpp"
#include "core/error.hpp"
#include "core/format.hpp"

namespace tridex::app::study {

namespace {

// A disk across the spine: a flat-end cylinder of `radius_m` and `thickness_m` centred on the spine at s.
compute::Sweep disk(const Tube& tube, ToolOp op, double s, double radius_m, double thickness_m) {
    const Vec3 t = tube.tangent_at(s), c = tube.point_at(s) - 0.5 * thickness_m * t;
    compute::Sweep sw;
    sw.op = op;
    sw.tool.kind = ToolKind::kFlatEnd;
    sw.tool.radius_m = radius_m;
    sw.tool.length_m = thickness_m;
    sw.path_m = Segment{c, c};
    sw.axis = t;
    return sw;
}

// Stacks disks along the extended spine from s0 to s1, at most `step` apart and twice as thick (so they overlap on
// the outside of a bend), each of the passage radius at its centre plus `extra`: the swept circular section.
void sweep_range(compute::TriDexel& m, const Tube& tube, ToolOp op, double s0, double s1, double step, double extra) {
    const int n = std::max(1, static_cast<int>(std::ceil((s1 - s0) / step)));
    for (int i = 0; i <= n; ++i) {
        const double s = s0 + (s1 - s0) * i / n;
        compute::apply_sweep(m, disk(tube, op, s, tube.passage_radius_m(s) + extra, 2.0 * step));
    }
}

void add_cap(compute::TriDexel& m, const Tube& tube, double s) {
    const TubeSpec& sp = tube.spec();
    compute::apply_sweep(m, disk(tube, ToolOp::kUnion, s, 0.5 * sp.cap_size_m, sp.cap_thickness_m));
}

}  // namespace

Workpiece felt_walls(const Tube& tube, const StudyModel& model, const std::string& source, const WallOptions& o) {
    const TubeSpec& sp = tube.spec();
    if (!(o.cell_m > 0.0 && o.cell_m <= sp.radius_m / 4.0))
        throw Error("study walls: cell_m " + format_number(o.cell_m) + " m must be in (0, radius_m / 4 = " +
                    format_number(sp.radius_m / 4.0) + "] m");
    if (!(o.wall_m >= 2.0 * o.cell_m && o.wall_m <= 0.1))
        throw Error("study walls: wall_m " + format_number(o.wall_m) + " m must be in [2 cells, 0.1] m");
    const auto t0 = std::chrono::steady_clock::now();
    const double len = tube.length_m(), fl = sp.funnel_length_m;
    const double reach = std::max(0.5 * sp.funnel_mouth_m + o.wall_m, 0.5 * std::sqrt(2.0) * sp.cap_size_m);
    Aabb box;
    for (double s = tube.start_cap_s_m(); s <= tube.end_cap_s_m() + 1e-9; s += 0.25 * reach) {
        box.add(tube.point_at(s) - Vec3(reach));
        box.add(tube.point_at(s) + Vec3(reach));
    }
    box.add(tube.point_at(tube.end_cap_s_m()) - Vec3(reach));
    box.add(tube.point_at(tube.end_cap_s_m()) + Vec3(reach));
    const Vec3 size = box.size();
    const int resolution = static_cast<int>(std::ceil(std::max({size.x, size.y, size.z}) / o.cell_m)) + 4;
    const compute::Lattice lattice = compute::Lattice::around(box, resolution);
    Workpiece wp;
    wp.mesh_path = source;
    wp.resolution = resolution;
    wp.model = compute::TriDexel::empty(lattice, model_memory_budget_bytes());
    const double step = 0.5 * o.cell_m;
    if (model.funnels.felt && fl > 0.0) {
        sweep_range(wp.model, tube, ToolOp::kUnion, -fl, 0.0, step, o.wall_m);
        sweep_range(wp.model, tube, ToolOp::kUnion, len, len + fl, step, o.wall_m);
    }
    if (model.tube.felt) sweep_range(wp.model, tube, ToolOp::kUnion, 0.0, len, step, o.wall_m);
    const double beyond = fl + 2.0 * o.cell_m;  // past the disks at the mouths
    sweep_range(wp.model, tube, ToolOp::kSubtract, -beyond, len + beyond, step, 0.0);
    if (model.caps.felt) {
        add_cap(wp.model, tube, tube.start_cap_s_m());
        add_cap(wp.model, tube, tube.end_cap_s_m());
    }
    wp.model.mark_dirty(lattice.bounds());
    wp.volume_dexel_m3 = compute::dexel_volume_m3(wp.model);
    wp.volume_mesh_m3 = wp.volume_dexel_m3;
    wp.scan_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return wp;
}

}  // namespace tridex::app::study
