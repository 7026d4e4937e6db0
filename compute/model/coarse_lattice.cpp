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
    const float inv = 1.0f / static_cast<float>(stride);
    for (int a = 0; a < 3; ++a) {
        const RaySet& f = fine.sets[a];
        RaySet& s = m.sets[a];
        for (int v = 0; v < s.nv; ++v) {
            const int fv = v * stride;
            if (fv >= f.nv) break;
            for (int u = 0; u < s.nu; ++u) {
                const int fu = u * stride;
                if (fu >= f.nu) break;
                const std::vector<Interval>& src = f.ray(fu, fv);
                std::vector<Interval>& dst = s.ray(u, v);
                dst.reserve(src.size());
                for (const Interval& iv : src)
                    dst.push_back({iv.enter * inv, iv.exit * inv, iv.enter_material, iv.exit_material});
            }
        }
    }
    m.tiles.dirty.assign(m.tiles.dirty.size(), TileGrid::kWhole);
    return m;
}

std::size_t coarse_model_bytes(const TriDexel& fine, int stride) {
    const Lattice lat = coarse_lattice(fine.lattice, stride);
    std::size_t bytes = 0;
    for (int a = 0; a < 3; ++a) {
        const RaySet& f = fine.sets[a];
        const int nu = lat.nodes((a + 1) % 3), nv = lat.nodes((a + 2) % 3);
        bytes += static_cast<std::size_t>(nu) * nv * sizeof(std::vector<Interval>);
        for (int v = 0; v * stride < f.nv && v < nv; ++v)
            for (int u = 0; u * stride < f.nu && u < nu; ++u)
                bytes += f.ray(u * stride, v * stride).size() * sizeof(Interval);
    }
    return bytes;
}

}  // namespace tridex::compute
