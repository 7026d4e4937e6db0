// compute/tools/boolean.cpp - the capsule (swept ball) subtraction, a ball-tool Sweep on the CPU reference.
#include "compute/tools/boolean.hpp"

#include <cmath>
#include <string>

#include "compute/tools/sweep.hpp"
#include "core/error.hpp"

namespace tridex::compute {

BooleanStats subtract_capsule(TriDexel& model, const Segment& seg_m, double radius_m) {
    if (!is_finite(seg_m.a) || !is_finite(seg_m.b)) throw Error("subtract_capsule: tool segment is not finite");
    if (!std::isfinite(radius_m) || !(radius_m > 0.0))
        throw Error("subtract_capsule: tool radius must be a positive number of metres, got " + std::to_string(radius_m));
    Sweep sweep;
    sweep.op = ToolOp::kSubtract;
    sweep.tool = SweepTool{ToolKind::kBall, radius_m, 0.0};
    sweep.path_m = seg_m;
    return apply_sweep(model, sweep);
}

}  // namespace tridex::compute
