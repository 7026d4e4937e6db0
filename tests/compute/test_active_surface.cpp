// tests/compute/test_active_surface.cpp - extract_active_surface: window placement and clamping,
// copied intervals, nearest-run truncation, and no heap allocation.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <memory>
#include <new>

#include "compute/runtime/active_surface_publish.hpp"
#include "core/primitives.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "core/error.hpp"

// Counts every heap allocation of this test program, to prove the extraction allocates nothing.
static std::atomic<long> g_allocations{0};
void* operator new(std::size_t n) {
    ++g_allocations;
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

using namespace tridex;
using namespace tridex::compute;

namespace {

/// 48-cell lattice (49 nodes per axis), 2 mm cells, holding the box [10, 40]^3 (grid units).
TriDexel box_model() {
    Lattice L;
    L.origin_m = Vec3(0.3, 0.1, -0.2);
    L.cell_m = 0.002;
    L.cells = {48, 48, 48};
    TriDexel m = TriDexel::empty(L, std::size_t{1} << 30);
    scan_convert(box_mesh(Aabb{L.to_world(Vec3(10.0)), L.to_world(Vec3(40.0))}), m);
    return m;
}

/// Every published ray equals the model's ray (all intervals, in order).
void expect_copied(const TriDexel& m, const ActiveSurface& s) {
    for (int a = 0; a < 3; ++a) {
        const auto& w = s.sets[a];
        for (int iv = 0; iv < ActiveSurface::kWindow; ++iv)
            for (int iu = 0; iu < ActiveSurface::kWindow; ++iu) {
                if (iu >= w.nu || iv >= w.nv) {
                    EXPECT_EQ(w.intervals(iu, iv), 0);
                    continue;
                }
                const auto& ray = m.sets[a].ray(w.u0 + iu, w.v0 + iv);
                ASSERT_EQ(w.intervals(iu, iv), static_cast<int>(ray.size()));
                for (std::size_t n = 0; n < ray.size(); ++n) {
                    EXPECT_EQ(w.enter(iu, iv, static_cast<int>(n)), ray[n].enter);
                    EXPECT_EQ(w.exit(iu, iv, static_cast<int>(n)), ray[n].exit);
                }
            }
    }
}

}  // namespace

TEST(ActiveSurface, CentredWindowCopiesRays) {
    const TriDexel m = box_model();
    auto out = std::make_unique<ActiveSurface>();
    const Vec3 c = m.lattice.to_world(Vec3(24.3, 20.6, 27.4));
    extract_active_surface(m, c, 0.0, 7, *out);
    EXPECT_EQ(out->sequence, 7u);
    EXPECT_EQ(out->origin_m, m.lattice.origin_m);
    EXPECT_EQ(out->cell_m, m.lattice.cell_m);
    EXPECT_EQ(out->nodes, (std::array<int, 3>{49, 49, 49}));
    EXPECT_EQ(out->centre_m, c);
    // Nearest nodes: x 24, y 21, z 27; window start = nearest - 16.
    EXPECT_EQ(out->sets[0].u0, 21 - 16);  // X rays: u = y
    EXPECT_EQ(out->sets[0].v0, 27 - 16);  // v = z
    EXPECT_EQ(out->sets[1].u0, 27 - 16);  // Y rays: u = z
    EXPECT_EQ(out->sets[1].v0, 24 - 16);  // v = x
    EXPECT_EQ(out->sets[2].u0, 24 - 16);  // Z rays: u = x
    EXPECT_EQ(out->sets[2].v0, 21 - 16);  // v = y
    for (const auto& w : out->sets) {
        EXPECT_EQ(w.nu, 32);
        EXPECT_EQ(w.nv, 32);
        EXPECT_FALSE(w.truncated);
    }
    expect_copied(m, *out);
    // The published point of a ray's entry is the box face: Z ray at node (20, 20) enters at z = 10.
    const auto& wz = out->sets[2];
    EXPECT_EQ(wz.enter(20 - wz.u0, 20 - wz.v0, 0), 10.0f);
    const Vec3 p = out->point(2, 20, 20, wz.enter(20 - wz.u0, 20 - wz.v0, 0));
    EXPECT_NEAR(p.z, m.lattice.to_world(Vec3(0, 0, 10)).z, 1e-12);
}

TEST(ActiveSurface, WindowClampsAtLatticeBorders) {
    const TriDexel m = box_model();
    auto out = std::make_unique<ActiveSurface>();
    extract_active_surface(m, m.lattice.to_world(Vec3(2.0, 47.0, -30.0)), 0.0, 1, *out);
    EXPECT_EQ(out->sets[2].u0, 0);        // x near 0
    EXPECT_EQ(out->sets[2].v0, 49 - 32);  // y near the far end
    EXPECT_EQ(out->sets[0].v0, 0);        // z beyond the lattice: clamped
    expect_copied(m, *out);
    // A lattice smaller than the window: the whole lattice, nu = nodes.
    Lattice L;
    L.cell_m = 0.01;
    L.cells = {10, 20, 40};
    TriDexel small = TriDexel::empty(L, 1 << 24);
    small.sets[2].ray(3, 4) = {{1.0f, 2.0f}};
    extract_active_surface(small, Vec3(0.05, 0.1, 0.2), 0.0, 2, *out);
    EXPECT_EQ(out->sets[2].nu, 11);
    EXPECT_EQ(out->sets[2].nv, 21);
    EXPECT_EQ(out->sets[2].u0, 0);
    EXPECT_EQ(out->sets[2].v0, 0);
    EXPECT_EQ(out->sets[0].nu, 21);  // X rays: u = y (21 nodes), v = z (41 nodes, window 32)
    EXPECT_EQ(out->sets[0].nv, 32);
    EXPECT_EQ(out->sets[0].v0, 20 - 16);
    expect_copied(small, *out);
}

TEST(ActiveSurface, TruncatesToTheNearestRun) {
    const TriDexel base = box_model();
    TriDexel m = base;
    // Ten unit intervals [2k, 2k+1] on the Z ray at node (24, 24).
    auto& ray = m.sets[2].ray(24, 24);
    ray.clear();
    for (int k = 0; k < 10; ++k) ray.push_back({2.0f * k, 2.0f * k + 1.0f});
    auto out = std::make_unique<ActiveSurface>();
    struct Case {
        double z;   // centre depth, grid units
        int first;  // first interval kept
    };
    // Depth 9.4: distances 0.4 (to [8,9]) and 0.6 ([10,11]), then 2.4 ([6,7]), 2.6 ([12,13]).
    for (const Case& c : {Case{9.4, 3}, Case{0.2, 0}, Case{30.0, 6}, Case{13.0, 5}, Case{12.6, 5}, Case{11.4, 4}}) {
        extract_active_surface(m, m.lattice.to_world(Vec3(24.0, 24.0, c.z)), 0.0, 3, *out);
        const auto& w = out->sets[2];
        EXPECT_TRUE(w.truncated);
        EXPECT_FALSE(out->sets[0].truncated);
        const int iu = 24 - w.u0, iv = 24 - w.v0;
        ASSERT_EQ(w.intervals(iu, iv), ActiveSurface::kMaxIntervals);
        for (int n = 0; n < ActiveSurface::kMaxIntervals; ++n) {
            EXPECT_EQ(w.enter(iu, iv, n), 2.0f * (c.first + n)) << "z " << c.z;
            EXPECT_EQ(w.exit(iu, iv, n), 2.0f * (c.first + n) + 1.0f) << "z " << c.z;
        }
    }
}

TEST(ActiveSurface, AllocatesNothingAndRefusesNonFiniteCentre) {
    const TriDexel m = box_model();
    auto out = std::make_unique<ActiveSurface>();
    const Vec3 c = m.lattice.to_world(Vec3(30.0, 30.0, 30.0));
    const long before = g_allocations.load();
    for (int i = 0; i < 100; ++i) extract_active_surface(m, c, 0.0, static_cast<std::uint64_t>(i), *out);
    EXPECT_EQ(g_allocations.load() - before, 0);
    out->sequence = 5;
    EXPECT_THROW(extract_active_surface(m, Vec3(NAN, 0, 0), 0.0, 6, *out), Error);
    EXPECT_EQ(out->sequence, 5u);
}

TEST(ActiveSurface, StrideChosenFromTheToolExtent) {
    // 0.3 mm cells (N=1000 on a 0.3 m stock), 300 cells = 90 mm a side, a box [40, 200]^3 cells.
    Lattice L;
    L.cell_m = 0.0003;
    L.cells = {300, 300, 300};
    TriDexel m = TriDexel::empty(L, std::size_t{1} << 30);
    scan_convert(box_mesh(Aabb{L.to_world(Vec3(40.0)), L.to_world(Vec3(200.0))}), m);
    auto out = std::make_unique<ActiveSurface>();
    const Vec3 c = L.to_world(Vec3(150.2, 149.6, 201.3));  // just above the box's top face
    // No extent and no margin: every ray (the old 32-ray window, 9.3 mm).
    extract_active_surface(m, c, 0.0, 1, *out, 0.0);
    for (const auto& w : out->sets) EXPECT_EQ(w.stride, 1);
    // A 16 mm ball (r = 8 mm) + the 3 mm default margin: reach 11 mm / (14.5 rays x 0.3 mm) = 2.53 -> 3.
    EXPECT_DOUBLE_EQ(tool_extent_m(0.0, 0.008), 0.016);
    EXPECT_DOUBLE_EQ(tool_extent_m(0.03, 0.0), 0.06);
    EXPECT_DOUBLE_EQ(tool_extent_m(NAN, -1.0), 0.0);
    extract_active_surface(m, c, tool_extent_m(0.0, 0.008), 2, *out);
    for (int a = 0; a < 3; ++a) {
        const auto& w = out->sets[a];
        EXPECT_EQ(w.stride, 3);
        EXPECT_EQ(w.nu, 32);
        EXPECT_EQ(w.nv, 32);
        EXPECT_EQ(w.u0 % 3, 0);
        EXPECT_EQ(w.v0 % 3, 0);
        // The window covers the reach on both sides of the centre.
        const ActiveSurface::WindowCoord lo = out->to_window(a, c - Vec3(0.011));
        const ActiveSurface::WindowCoord hi = out->to_window(a, c + Vec3(0.011));
        EXPECT_GE(lo.fu, 0.0);
        EXPECT_GE(lo.fv, 0.0);
        EXPECT_LE(hi.fu, w.nu - 1);
        EXPECT_LE(hi.fv, w.nv - 1);
        // Every window ray is the model's strided ray.
        for (int iv = 0; iv < w.nv; ++iv)
            for (int iu = 0; iu < w.nu; ++iu) {
                const std::array<int, 2> uv = out->lattice_ray(a, iu, iv);
                EXPECT_EQ(uv[0], w.u0 + 3 * iu);
                const auto& ray = m.sets[a].ray(uv[0], uv[1]);
                ASSERT_EQ(w.intervals(iu, iv), static_cast<int>(ray.size()));
                for (std::size_t n = 0; n < ray.size(); ++n) {
                    EXPECT_EQ(w.enter(iu, iv, static_cast<int>(n)), ray[n].enter);
                    EXPECT_EQ(w.exit(iu, iv, static_cast<int>(n)), ray[n].exit);
                }
            }
    }
    // The 5-DOF wand (+-30 mm): reach 33 mm -> 7.6 -> stride 8; near the lattice end the window is clamped
    // inside it (the lattice's 301 nodes hold 38 rays at that stride).
    extract_active_surface(m, c, tool_extent_m(0.03, 0.0), 3, *out);
    EXPECT_EQ(out->sets[2].stride, 8);
    EXPECT_EQ(out->sets[2].nu, 32);
    EXPECT_EQ(out->sets[0].v0, 300 - 8 * 31);  // X rays: v = z, centre 201 + 16 strides > 300
    // Bad extents throw before touching the output.
    EXPECT_THROW(extract_active_surface(m, c, -1.0, 4, *out), Error);
    EXPECT_THROW(extract_active_surface(m, c, 0.01, 4, *out, NAN), Error);
    EXPECT_EQ(out->sequence, 3u);
}
