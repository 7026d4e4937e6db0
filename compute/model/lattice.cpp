// compute/model/lattice.cpp - choosing the lattice around a workpiece.
#include "compute/model/lattice.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tridex::compute {

Lattice Lattice::around(const Aabb& box, int resolution, int margin_cells) {
    if (margin_cells < 1) throw Error("lattice: margin_cells must be >= 1, got " + std::to_string(margin_cells));
    if (resolution < 2 * margin_cells + 2)
        throw Error("lattice: --resolution must be at least " + std::to_string(2 * margin_cells + 2) +
                    " cells, got " + std::to_string(resolution));
    const Vec3 size = box.size();
    const double longest = std::max({size.x, size.y, size.z});
    if (box.empty() || !is_finite(size) || !(longest > 0.0))
        throw Error("lattice: the workpiece bounding box is empty or not finite");
    Lattice l;
    l.cell_m = longest / (resolution - 2 * margin_cells);
    Vec3 lo;
    for (int a = 0; a < 3; ++a) {
        const int inner = std::max(1, static_cast<int>(std::ceil(size[a] / l.cell_m - 1e-9)));
        l.cells[a] = inner + 2 * margin_cells;
        const double pad = 0.5 * (l.cells[a] * l.cell_m - size[a]);  // centre the box in the lattice
        lo[a] = box.lo[a] - pad;
    }
    l.origin_m = lo;
    return l;
}

}  // namespace tridex::compute
