// tests/compute/test_volume_faces.cpp - dexel volume of analytic cuts into box faces on lattice nodes.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>

#include "compute/mesh/scan_convert.hpp"
#include "compute/model/volume.hpp"
#include "compute/tools/boolean.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"

using namespace tridex;
using namespace tridex::compute;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kCells = 64;
constexpr double kLo = 8.0, kHi = 56.0;  // box [kLo, kHi]^3 in grid units: every face on nodes

/// The box workpiece on a 64-cell lattice of 1 mm cells, faces on nodes (shifted by `shift` cells).
TriDexel box_on_nodes(double shift = 0.0) {
    Lattice L;
    L.origin_m = Vec3(0.01, -0.02, 0.005);
    L.cell_m = 0.001;
    L.cells = {kCells, kCells, kCells};
    TriDexel m = TriDexel::empty(L, std::size_t{1} << 30);
    scan_convert(box_mesh(Aabb{L.to_world(Vec3(kLo + shift)), L.to_world(Vec3(kHi + shift))}), m);
    return m;
}

double cells3(const TriDexel& m, double v_m3) { return v_m3 / std::pow(m.lattice.cell_m, 3); }

/// Volume of the three sets without the face correction (the plain midpoint rule), cells^3.
double raw_cells3(const TriDexel& m) {
    return cells3(m, (ray_set_volume_m3(m, 0) + ray_set_volume_m3(m, 1) + ray_set_volume_m3(m, 2)) / 3.0);
}

struct Cut {
    double exact, dexel, raw;  // cells^3
};

/// Subtracts a capsule (grid units a-b, radius r) and reports the removed volume three ways.
Cut cut(TriDexel& m, const Vec3& a, const Vec3& b, double r, double exact) {
    const double v0 = cells3(m, dexel_volume_m3(m)), raw0 = raw_cells3(m);
    subtract_capsule(m, Segment{m.lattice.to_world(a), m.lattice.to_world(b)}, r * m.lattice.cell_m);
    return {exact, v0 - cells3(m, dexel_volume_m3(m)), raw0 - raw_cells3(m)};
}

void report(const char* what, const Cut& c) {
    std::cout << "[ volume   ] " << what << ": exact " << c.exact << " cells^3, dexel " << c.dexel << " (error "
              << c.dexel - c.exact << "), plain midpoint rule " << c.raw << " (error " << c.raw - c.exact << ")\n";
}

}  // namespace

TEST(VolumeFaces, UncutBoxOnNodesIsExactAndItsCorrectionIsZero) {
    const TriDexel m = box_on_nodes();
    const double side = kHi - kLo;
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(cells3(m, ray_set_volume_m3(m, a)), side * side * side, 1e-6);
        EXPECT_NEAR(cells3(m, lattice_face_correction_m3(m, a)), 0.0, 1e-9);
    }
    EXPECT_NEAR(cells3(m, dexel_volume_m3(m)), side * side * side, 1e-6);
    EXPECT_THROW(lattice_face_correction_m3(m, 3), Error);
}

// A ball centred on the top face removes a hemisphere. The plain midpoint rule misses a slab of
// half a cell under the face in the two sets whose rays lie in the face: an error near
// (2/3) * pi r^2 * (1/2) cells^3, of order h. With the trapezoid correction only the midpoint rule's
// error on the curved surface remains.
TEST(VolumeFaces, BallCutIntoTopFaceOnNodesRemovesAHemisphere) {
    TriDexel m = box_on_nodes();
    const double r = 10.4;
    const Cut c = cut(m, Vec3(31.3, 32.7, kHi), Vec3(31.3, 32.7, kHi), r, 2.0 / 3.0 * kPi * r * r * r);
    report("hemisphere r = 10.4 cells, top face", c);
    EXPECT_LT(std::abs(c.dexel - c.exact), 0.004 * c.exact);       // 0.4% of the cut, about 9 cells^3
    EXPECT_GT(c.exact - c.raw, 0.25 * kPi * r * r);                // the bias this test pins is real
}

TEST(VolumeFaces, BallCutIntoBottomFaceOnNodesRemovesAHemisphere) {
    TriDexel m = box_on_nodes();
    const double r = 9.7;
    const Cut c = cut(m, Vec3(30.6, 31.2, kLo), Vec3(30.6, 31.2, kLo), r, 2.0 / 3.0 * kPi * r * r * r);
    report("hemisphere r = 9.7 cells, bottom face", c);
    EXPECT_LT(std::abs(c.dexel - c.exact), 0.004 * c.exact);
    EXPECT_LT(c.exact - c.raw, -0.25 * kPi * r * r);  // the plain rule's bias has the other sign here
}

// A capsule whose axis lies in the +x face (oblique to y and z) removes half a capsule. With the face
// on nodes the sets whose rays lie in it integrate across the capsule by the trapezoid rule, whose
// error on the curved surface (order h^2) is about twice the midpoint rule's that the same cut with the
// face between nodes shows, and of the other sign: both stay within 1% here, the plain rule on nodes
// does not.
TEST(VolumeFaces, CapsuleAlongASideFaceOnNodesRemovesHalfACapsule) {
    const double r = 6.3;
    const Vec3 a(kHi, 18.2, 20.9), b(kHi, 41.5, 37.3);
    const double len = glm::length(b - a), exact = 0.5 * (kPi * r * r * len + 4.0 / 3.0 * kPi * r * r * r);
    TriDexel on = box_on_nodes(), off = box_on_nodes(0.5);
    const Cut c = cut(on, a, b, r, exact), c_off = cut(off, a + Vec3(0.5), b + Vec3(0.5), r, exact);
    report("half capsule r = 6.3 cells, +x face", c);
    report("half capsule r = 6.3 cells, +x face between nodes", c_off);
    EXPECT_LT(std::abs(c.dexel - c.exact), 0.01 * c.exact);
    EXPECT_LT(std::abs(c_off.dexel - c.exact), 0.01 * c.exact);
    EXPECT_GT(c.exact - c.raw, 0.25 * (2.0 * r * len + kPi * r * r));
}

// With every face half way between nodes the midpoint rule is already unbiased: the correction is
// exactly zero.
TEST(VolumeFaces, FacesHalfWayBetweenNodesNeedNoCorrection) {
    TriDexel m = box_on_nodes(0.5);
    const double r = 10.4;
    const Cut c = cut(m, Vec3(31.3, 32.7, kHi + 0.5), Vec3(31.3, 32.7, kHi + 0.5), r, 2.0 / 3.0 * kPi * r * r * r);
    report("hemisphere r = 10.4 cells, top face half way between nodes", c);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(lattice_face_correction_m3(m, a), 0.0);
    EXPECT_LT(std::abs(c.dexel - c.exact), 0.004 * c.exact);
}

// Faces at another offset (0.37 cell above the nodes): the box stays exact, and a hemisphere cut into
// the top face is measured without the order-h bias the plain rule has there.
TEST(VolumeFaces, BallCutIntoTopFaceOffTheNodes) {
    TriDexel m = box_on_nodes(0.37);
    const double side = kHi - kLo;
    EXPECT_NEAR(cells3(m, dexel_volume_m3(m)), side * side * side, 0.05);  // face depths rounded to float
    const double r = 10.4;
    const Cut c = cut(m, Vec3(31.3, 32.7, kHi + 0.37), Vec3(31.3, 32.7, kHi + 0.37), r, 2.0 / 3.0 * kPi * r * r * r);
    report("hemisphere r = 10.4 cells, top face 0.37 cell above nodes", c);
    EXPECT_LT(std::abs(c.dexel - c.exact), 0.004 * c.exact);
    EXPECT_GT(c.raw - c.exact, 0.05 * kPi * r * r);  // the plain rule removes 0.13 cell x the face's cut area too much
}

// Hand-built rays: six Z rays end exactly at z = 3 on nodes (1..3, 3..4, 3), a patch of a flat face
// (their entries differ, so they form no face). The X ray through row y = 3 covers only node x = 2:
// half weight there (-1/2 cell^3) and for the uncovered face nodes (+1/2 each); the Y rays through the
// patch are empty (+1/2 at each of the six nodes). The Z set is not corrected by its own ends.
TEST(VolumeFaces, HandBuiltFacePatchGetsPartialColumns) {
    Lattice L;
    L.cell_m = 0.5;
    L.cells = {4, 5, 6};
    TriDexel m = TriDexel::empty(L, 1 << 20);
    const double h3 = 0.125;
    auto face_at = [&m](float z) {
        for (int y = 3; y <= 4; ++y)
            for (int x = 1; x <= 3; ++x) m.sets[2].ray(x, y) = {{0.125f * static_cast<float>(x + 3 * y), z}};
    };
    face_at(3.0f);
    m.sets[0].ray(3, 3) = {{1.5f, 2.5f}};
    EXPECT_DOUBLE_EQ(lattice_face_correction_m3(m, 0), (0.5 - 0.5 + 0.5 + 3 * 0.5) * h3);
    EXPECT_DOUBLE_EQ(lattice_face_correction_m3(m, 1), 6 * 0.5 * h3);
    EXPECT_DOUBLE_EQ(lattice_face_correction_m3(m, 2), 0.0);
    // The face at z = 2.75 instead: node 3's column [2.5, 3.5] holds a quarter of material, which the
    // X ray at (y = 3, z = 3) counts as 1 at x = 2 (-3/4) and the other face nodes count as 0 (+1/4).
    face_at(2.75f);
    EXPECT_DOUBLE_EQ(lattice_face_correction_m3(m, 0), (0.25 - 0.75 + 0.25 + 3 * 0.25) * h3);
    // A single row: the surface does not continue along y, so for X it is a wall parallel to its rays
    // (which Y's rays would cross too) and Z's ends correct each column half; a lone end is a surface
    // crossing, not a face or a wall.
    for (int x = 1; x <= 3; ++x) m.sets[2].ray(x, 4).clear();
    EXPECT_DOUBLE_EQ(lattice_face_correction_m3(m, 0), 0.5 * (0.25 - 0.75 + 0.25) * h3);
    m.sets[2].ray(1, 3).clear();
    m.sets[2].ray(3, 3).clear();
    EXPECT_DOUBLE_EQ(lattice_face_correction_m3(m, 1), 0.0);
}
