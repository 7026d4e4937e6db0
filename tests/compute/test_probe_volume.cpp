// tests/compute/test_probe_volume.cpp - dexel_volume_m3 on hand-built rays, probe_top on a box.
#include <gtest/gtest.h>

#include "core/primitives.hpp"
#include "compute/model/probe.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/volume.hpp"
#include "core/error.hpp"

using namespace tridex;
using namespace tridex::compute;

namespace {

Lattice small_lattice() {
    Lattice L;
    L.origin_m = Vec3(1.0, 2.0, -3.0);
    L.cell_m = 0.5;
    L.cells = {4, 5, 6};
    return L;
}

}  // namespace

TEST(DexelVolume, SumsIntervalLengthsTimesCellVolumeAveraged) {
    TriDexel m = TriDexel::empty(small_lattice(), 1 << 20);
    // No end on a node, so the lattice-face correction is zero and only the sums count.
    m.sets[0].ray(1, 2) = {{0.5f, 1.5f}, {2.25f, 3.5f}};  // 2.25 cells
    m.sets[1].ray(0, 0) = {{1.25f, 4.25f}};               // 3 cells
    m.sets[2].ray(3, 4) = {{0.125f, 0.875f}};             // 0.75 cells
    const double h3 = 0.125;
    EXPECT_DOUBLE_EQ(ray_set_volume_m3(m, 0), 2.25 * h3);
    EXPECT_DOUBLE_EQ(ray_set_volume_m3(m, 1), 3.0 * h3);
    EXPECT_DOUBLE_EQ(ray_set_volume_m3(m, 2), 0.75 * h3);
    EXPECT_DOUBLE_EQ(dexel_volume_m3(m), 6.0 / 3.0 * h3);
    EXPECT_THROW(ray_set_volume_m3(m, 3), Error);
    EXPECT_DOUBLE_EQ(dexel_volume_m3(TriDexel::empty(small_lattice(), 1 << 20)), 0.0);
}

TEST(ProbeTop, NearestRayTopOfABox) {
    TriDexel m = TriDexel::empty(small_lattice(), 1 << 20);
    const Lattice& L = m.lattice;
    // Box [1, 3.5] x [1, 4.5] x [2, 5.25] in grid units.
    scan_convert(box_mesh(Aabb{L.to_world(Vec3(1, 1, 2)), L.to_world(Vec3(3.5, 4.5, 5.25))}), m);
    Vec3 top(-1.0);
    // Above node (2, 3) (grid point (2.2, 2.8) rounds to it): the Z ray's top is z = 5.25.
    ASSERT_TRUE(probe_top(m, 2, L.to_world(Vec3(2.2, 2.8, 9.0)), top));
    EXPECT_NEAR(top.x, L.to_world(Vec3(2, 3, 5.25)).x, 1e-12);
    EXPECT_NEAR(top.y, L.to_world(Vec3(2, 3, 5.25)).y, 1e-12);
    EXPECT_NEAR(top.z, L.to_world(Vec3(2, 3, 5.25)).z, 1e-12);
    // X set: the ray through (y, z) nearest (3.4, 4.6) is (3, 5); its top is x = 3.5.
    ASSERT_TRUE(probe_top(m, 0, L.to_world(Vec3(-7.0, 3.4, 4.6)), top));
    EXPECT_NEAR(top.x, L.to_world(Vec3(3.5, 3, 5)).x, 1e-12);
    // Outside the box's footprint (node (4, 3) is beyond x = 3.5): empty ray.
    const Vec3 before = top;
    EXPECT_FALSE(probe_top(m, 2, L.to_world(Vec3(3.8, 3.0, 0.0)), top));
    EXPECT_EQ(top, before);
    // Far outside the lattice: clamped to the border node (0, 0), which is empty.
    EXPECT_FALSE(probe_top(m, 2, Vec3(-100.0, -100.0, 0.0), top));
    EXPECT_THROW(probe_top(m, 3, Vec3(0.0), top), Error);
    EXPECT_THROW(probe_top(m, -1, Vec3(0.0), top), Error);
    EXPECT_THROW(probe_top(m, 2, Vec3(NAN, 0.0, 0.0), top), Error);
}
