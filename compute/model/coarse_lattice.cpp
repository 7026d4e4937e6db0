// compute/model/coarse_lattice.cpp - every stride-th ray of a tri-dexel model, on a lattice stride times coarser.
#include "compute/model/coarse_lattice.hpp"

#include <string>

#include "core/error.hpp"

namespace tridex::compute {

namespace {

bool power_of_two(int s) { return s > 0 && (s & (s - 1)) == 0; }

}  // namespace

Lattice coarse_lattice(const Lattice& fine, int stride) {
    if (!power_of_two(stride) || stride > kMaxLatticeStride)
        throw Error("coarse lattice: stride " + std::to_string(stride) + " must be a power of two in 1.." +
                    std::to_string(kMaxLatticeStride));
    Lattice c = fine;
    c.cell_m = fine.cell_m * stride;
    for (int a = 0; a < 3; ++a) c.cells[a] = (fine.cells[a] + stride - 1) / stride;
    return c;
}

TriDexel coarse_model(const TriDexel& fine, int stride) {
    const Lattice lat = coarse_lattice(fine.lattice, stride);
    TriDexel m = TriDexel::empty(lat, ~std::size_t{0});
    for (int a = 0; a < 3; ++a) {
        const RaySet& f = fine.sets[a];
        RaySet& s = m.sets[a];
        for (int v = 0; v < s.nv; ++v) {
            const int fv = v * stride;
            if (fv >= f.nv) break;
            for (int u = 0; u < s.nu; ++u) {
                const int fu = u * stride;
                if (fu >= f.nu) break;
                coarse_ray(f.ray(fu, fv), stride, s.ray(u, v));
            }
        }
    }
    m.tiles.dirty.assign(m.tiles.dirty.size(), TileGrid::kWhole);
    return m;
}

void coarse_ray(const std::vector<Interval>& fine_ray, int stride, std::vector<Interval>& out) {
    const float inv = 1.0f / static_cast<float>(stride);
    out.clear();
    out.reserve(fine_ray.size());
    for (const Interval& iv : fine_ray) out.push_back({iv.enter * inv, iv.exit * inv, iv.enter_material, iv.exit_material});
}

}  // namespace tridex::compute
