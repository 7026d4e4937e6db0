// Tests of the model read on a coarser lattice (compute/model/coarse_lattice.hpp): every stride-th ray scaled, bit
// for bit the model a scan at the coarse spacing gives, contoured closed and near the analytic sphere, its paint
// kept, and bad strides refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/surface_distance.hpp"
#include "compute/model/coarse_lattice.hpp"
#include "core/error.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using testing::cube_lattice;
using testing::empty_model;
using testing::fill_rays;

bool same_float(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A sphere of radius r (grid units) about c on a cube lattice of `cells`, rays from its exact chords.
TriDexel sphere(int cells, const Vec3& c, double r) {
    TriDexel m = empty_model(cube_lattice(cells));
    fill_rays(m, [&](int a, int u, int v) { return testing::sphere_chord(c, r, a, u, v); });
    return m;
}

TEST(CoarseLattice, EveryCoarseRayIsTheFineRayScaledWithItsMaterials) {
    TriDexel fine = testing::random_voxels(40, 0.45, 7);
    for (RaySet& s : fine.sets)
        for (auto& ray : s.rays)
            for (Interval& iv : ray) {
                iv.enter_material = static_cast<std::uint8_t>(static_cast<int>(iv.enter) % 5);
                iv.exit_material = static_cast<std::uint8_t>(static_cast<int>(iv.exit) % 7);
            }
    for (int stride : {1, 2, 4, 8}) {
        const TriDexel c = coarse_model(fine, stride);
        EXPECT_EQ(c.lattice.origin_m, fine.lattice.origin_m);
        EXPECT_DOUBLE_EQ(c.lattice.cell_m, fine.lattice.cell_m * stride);
        for (int a = 0; a < 3; ++a) {
            EXPECT_EQ(c.lattice.cells[a], (40 + stride - 1) / stride);
            const RaySet &cs = c.sets[a], &fs = fine.sets[a];
            for (int v = 0; v < cs.nv; ++v)
                for (int u = 0; u < cs.nu; ++u) {
                    const auto& cr = cs.ray(u, v);
                    if (u * stride >= fs.nu || v * stride >= fs.nv) {
                        EXPECT_TRUE(cr.empty());
                        continue;
                    }
                    const auto& fr = fs.ray(u * stride, v * stride);
                    ASSERT_EQ(cr.size(), fr.size()) << "stride " << stride << " set " << a << " ray " << u << "," << v;
                    for (std::size_t i = 0; i < cr.size(); ++i) {
                        EXPECT_TRUE(same_float(cr[i].enter * static_cast<float>(stride), fr[i].enter));
                        EXPECT_TRUE(same_float(cr[i].exit * static_cast<float>(stride), fr[i].exit));
                        EXPECT_EQ(cr[i].enter_material, fr[i].enter_material);
                        EXPECT_EQ(cr[i].exit_material, fr[i].exit_material);
                    }
                }
        }
        for (std::uint8_t d : c.tiles.dirty) EXPECT_EQ(d, TileGrid::kWhole);
    }
}

// The coarse model of a sphere is, bit for bit, the sphere's model built at the coarse spacing: reading every
// stride-th ray loses nothing a scan at that spacing would have kept.
TEST(CoarseLattice, EqualsTheSphereBuiltAtTheCoarseSpacing) {
    const Vec3 centre(64.3, 63.7, 64.1);
    const double r = 50.2;
    const TriDexel fine = sphere(128, centre, r);
    for (int stride : {2, 4, 8}) {
        const TriDexel c = coarse_model(fine, stride);
        TriDexel direct = empty_model(coarse_lattice(fine.lattice, stride));
        fill_rays(direct, [&](int a, int u, int v) { return testing::sphere_chord(centre / double(stride), r / stride, a, u, v); });
        std::size_t ends = 0, differ = 0;
        for (int a = 0; a < 3; ++a)
            for (std::size_t i = 0; i < c.sets[a].rays.size(); ++i) {
                const auto &x = c.sets[a].rays[i], &y = direct.sets[a].rays[i];
                ASSERT_EQ(x.size(), y.size());
                for (std::size_t k = 0; k < x.size(); ++k, ++ends)
                    differ += !same_float(x[k].enter, y[k].enter) || !same_float(x[k].exit, y[k].exit);
            }
        EXPECT_GT(ends, 0u);
        EXPECT_EQ(differ, 0u) << "stride " << stride;
    }
}

// Contoured, each coarse model is a closed 2-manifold whose vertices lie near the analytic sphere; the error grows
// with the coarse cell and the triangles fall as its square.
TEST(CoarseLattice, ContourIsClosedAndNearTheAnalyticSphere) {
    const Vec3 centre(64.3, 63.7, 64.1);
    const double r = 50.2;
    const TriDexel fine = sphere(128, centre, r);
    const double h = fine.lattice.cell_m;
    std::size_t full_triangles = 0;
    for (int stride : {1, 2, 4, 8}) {
        TriDexel c = coarse_model(fine, stride);
        Contourer contour(c);
        contour.update(c);
        const TriMesh mesh = contour.mesh();
        testing::expect_closed_manifold(mesh);
        double worst = 0.0;
        const Vec3 centre_m = fine.lattice.to_world(centre);
        for (const Vec3& p : mesh.positions) worst = std::max(worst, std::abs(glm::length(p - centre_m) - r * h));
        // Points of the triangles too (a tenth of a fine cell apart): the chords' sag between vertices.
        double worst_face = worst;
        for (const Vec3& p : surface_samples(mesh, 0.1 * h))
            worst_face = std::max(worst_face, std::abs(glm::length(p - centre_m) - r * h));
        if (stride == 1) full_triangles = mesh.triangles.size();
        std::printf("[coarse lattice] stride %d: %zu triangles (%.4f of full); vertices within %.3g m of the sphere "
                    "(%.3f fine cells, %.3f coarse), faces within %.3g m (%.3f fine cells, %.3f coarse)\n",
                    stride, mesh.triangles.size(), double(mesh.triangles.size()) / double(full_triangles), worst,
                    worst / h, worst / (h * stride), worst_face, worst_face / h, worst_face / (h * stride));
        EXPECT_LT(worst, 0.1 * h * stride) << "stride " << stride;
        EXPECT_LT(worst_face, 0.1 * h * stride) << "stride " << stride;
        if (stride > 1) {
            EXPECT_LT(double(mesh.triangles.size()), 1.5 * double(full_triangles) / (stride * stride));
            EXPECT_GT(double(mesh.triangles.size()), 0.5 * double(full_triangles) / (stride * stride));
        }
    }
}

// A painted cap (material 3 on interval ends above the sphere's equator plus half its radius) stays painted on the
// coarse contour, and only there.
TEST(CoarseLattice, KeepsThePaintOnTheCoarseContour) {
    const Vec3 centre(32.4, 31.6, 32.2);
    const double r = 24.3;
    TriDexel fine = sphere(64, centre, r);
    for (int a = 0; a < 3; ++a)
        for (int v = 0; v < fine.sets[a].nv; ++v)
            for (int u = 0; u < fine.sets[a].nu; ++u)
                for (Interval& iv : fine.sets[a].ray(u, v)) {
                    const Vec3 pe = testing::ray_point(a, u, v, iv.enter), px = testing::ray_point(a, u, v, iv.exit);
                    if (pe.z > centre.z + 0.5 * r) iv.enter_material = 3;
                    if (px.z > centre.z + 0.5 * r) iv.exit_material = 3;
                }
    TriDexel c = coarse_model(fine, 4);
    Contourer contour(c);
    contour.update(c);
    const TriMesh mesh = contour.mesh();
    const std::vector<std::uint8_t> mat = contour.mesh_materials();
    ASSERT_EQ(mat.size(), mesh.positions.size());
    const Vec3 top = fine.lattice.to_world(centre + Vec3(0.0, 0.0, 0.5 * r));
    std::size_t painted = 0;
    for (std::size_t i = 0; i < mat.size(); ++i) {
        const double above_m = mesh.positions[i].z - top.z, cell = c.lattice.cell_m;
        if (above_m > cell) {
            EXPECT_EQ(mat[i], 3) << i;
        }
        if (above_m < -cell) {
            EXPECT_EQ(mat[i], 0) << i;
        }
        painted += mat[i] == 3;
    }
    EXPECT_GT(painted, 10u);
}

TEST(CoarseLattice, RefusesAStrideThatIsNotAPowerOfTwoInRange) {
    const TriDexel m = sphere(32, Vec3(16.0), 10.0);
    for (int bad : {0, -2, 3, 6, 128}) {
        try {
            (void)coarse_model(m, bad);
            ADD_FAILURE() << bad;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("stride " + std::to_string(bad)), std::string::npos) << e.what();
        }
    }
}

}  // namespace
}  // namespace tridex::compute
