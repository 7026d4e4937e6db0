// compute/model/volume.cpp - summing interval lengths of the ray sets.
#include "compute/model/volume.hpp"

#include <string>

#include "core/error.hpp"

namespace tridex::compute {

double ray_set_volume_m3(const TriDexel& model, int axis) {
    if (axis < 0 || axis > 2) throw Error("ray_set_volume_m3: axis must be 0, 1 or 2, got " + std::to_string(axis));
    double cells = 0.0;  // grid units: cell-length columns of one cell^2 cross-section
    for (const auto& ray : model.sets[axis].rays)
        for (const Interval& iv : ray) cells += static_cast<double>(iv.exit) - static_cast<double>(iv.enter);
    const double h = model.lattice.cell_m;
    return cells * h * h * h;
}

double dexel_volume_m3(const TriDexel& model) {
    return (ray_set_volume_m3(model, 0) + ray_set_volume_m3(model, 1) + ray_set_volume_m3(model, 2)) / 3.0;
}

}  // namespace tridex::compute
