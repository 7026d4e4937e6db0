// tests/compute/tdx_test_models.hpp - models for the .tdx tests: a sculpted sphere, and a bitwise comparison.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "compute/mesh/scan_convert.hpp"
#include "compute/model/tridexel.hpp"
#include "compute/tools/sweep.hpp"
#include "core/primitives.hpp"

namespace tdx_test {

using namespace tridex;
using namespace tridex::compute;

/// A sphere scan-converted on a `cells`^3 lattice, then `strokes` random subtract/union/paint ball and flat-end
/// sweeps (materials 1..6), so rays hold several intervals with several materials.
inline TriDexel sculpted_sphere(int cells, int strokes, std::uint32_t seed) {
    Lattice L;
    L.origin_m = Vec3(-0.3, 0.1, 0.25);
    L.cell_m = 0.002;
    L.cells = {cells, cells + 3, cells - 2};
    TriDexel m = TriDexel::empty(L, std::size_t{1} << 30);
    const Vec3 c = L.to_world(Vec3(cells / 2.0));
    scan_convert(icosphere_mesh(c, 0.36 * cells * L.cell_m, 3), m);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.2, 0.8), unit(0.0, 1.0);
    for (int i = 0; i < strokes; ++i) {
        Sweep s;
        const double pick = unit(rng);
        s.op = pick < 0.5 ? ToolOp::kSubtract : pick < 0.8 ? ToolOp::kUnion : ToolOp::kPaint;
        s.material = static_cast<std::uint8_t>(1 + rng() % 6);
        s.tool = SweepTool{unit(rng) < 0.3 ? ToolKind::kFlatEnd : ToolKind::kBall, (1.0 + 4.0 * unit(rng)) * L.cell_m,
                           6.0 * L.cell_m};
        const Vec3 a = L.to_world(Vec3(u(rng), u(rng), u(rng)) * double(cells));
        const Vec3 b = L.to_world(Vec3(u(rng), u(rng), u(rng)) * double(cells));
        s.path_m = Segment{a, b};
        apply_sweep(m, s);
    }
    return m;
}

/// Bitwise equality of two models: lattice, every ray's intervals (float bits and materials), tiles.
inline void expect_identical(const TriDexel& a, const TriDexel& b) {
    EXPECT_EQ(a.lattice.origin_m, b.lattice.origin_m);
    EXPECT_EQ(a.lattice.cell_m, b.lattice.cell_m);
    EXPECT_EQ(a.lattice.cells, b.lattice.cells);
    EXPECT_EQ(a.tiles.tiles, b.tiles.tiles);
    // Files keep which tiles are dirty, not which of their cells (TileGrid::kPartial loads as kWhole).
    ASSERT_EQ(a.tiles.dirty.size(), b.tiles.dirty.size());
    for (std::size_t t = 0; t < a.tiles.dirty.size(); ++t)
        EXPECT_EQ(a.tiles.dirty[t] != 0, b.tiles.dirty[t] != 0) << "tile " << t;
    std::size_t differing = 0;
    for (int s = 0; s < 3; ++s) {
        ASSERT_EQ(a.sets[s].rays.size(), b.sets[s].rays.size());
        EXPECT_EQ(a.sets[s].nu, b.sets[s].nu);
        EXPECT_EQ(a.sets[s].nv, b.sets[s].nv);
        for (std::size_t r = 0; r < a.sets[s].rays.size(); ++r) {
            const auto& x = a.sets[s].rays[r];
            const auto& y = b.sets[s].rays[r];
            bool same = x.size() == y.size();
            for (std::size_t k = 0; same && k < x.size(); ++k)
                same = std::memcmp(&x[k].enter, &y[k].enter, 4) == 0 && std::memcmp(&x[k].exit, &y[k].exit, 4) == 0 &&
                       x[k].enter_material == y[k].enter_material && x[k].exit_material == y[k].exit_material;
            differing += same ? 0 : 1;
        }
    }
    EXPECT_EQ(differing, 0u) << "rays that differ";
}

}  // namespace tdx_test
