// Materials: the table's validation, and the god-object taking stiffness, damping and friction from the
// material id of the interval it touches.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <string>

#include "core/error.hpp"
#include "haptics/god_object.hpp"
#include "haptics/materials.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

constexpr double kH = 1e-3;   // cell, m
constexpr float kC = 10.25f;  // plane height, cells
constexpr double kDt = 1e-3;  // s

Vec3 mm(double x, double y, double z) { return Vec3(x, y, z) * 1e-3; }

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(Materials, TableValidatesAndDefaults) {
    MaterialTable t;
    EXPECT_EQ(t[0].stiffness_n_per_m, 700.0);
    EXPECT_EQ(t[255].damping_n_s_per_m, 0.5);
    EXPECT_EQ(t[17].static_friction, 0.0);
    EXPECT_NE(message_of([&] { t.set(256, Material{}); }).find("256"), std::string::npos);
    EXPECT_NE(message_of([&] { t.set(-1, Material{}); }).find("-1"), std::string::npos);
    EXPECT_NE(message_of([&] { t.set(3, Material{-5.0, 0.5, 0.0, 0.0}); }).find("MaterialTable[3].stiffness_n_per_m"),
              std::string::npos);
    EXPECT_NE(message_of([&] { t.set(4, Material{700.0, 0.5, 0.2, 0.3}); }).find("MaterialTable[4].dynamic_friction"),
              std::string::npos);
    EXPECT_THROW(MaterialTable(Material{700.0, std::nan(""), 0.0, 0.0}), Error);
    t.set(9, Material{300.0, 1.0, 0.4, 0.3});
    EXPECT_EQ(t[9].stiffness_n_per_m, 300.0);
    EXPECT_EQ(t[8].stiffness_n_per_m, 700.0);
    const MaterialTable all(Material{100.0, 0.0, 0.1, 0.1});
    EXPECT_EQ(all[200].stiffness_n_per_m, 100.0);
}

// The plane z = kC on Z rays; rays at lattice x >= 16 carry material 7, the others material 0.
std::unique_ptr<ActiveSurface> two_materials() {
    auto s = test::z_plane(kH, kC);
    ActiveSurface::Window& w = s->sets[2];
    for (int iv = 0; iv < ActiveSurface::kWindow; ++iv)
        for (int iu = 16; iu < ActiveSurface::kWindow; ++iu) w.material[(iu + ActiveSurface::kWindow * iv) * 4] = 7;
    return s;
}

double pressed_force(const ActiveSurface& s, const ContactParams& p, double x, int* material = nullptr,
                     double y = 10.3) {
    GodObject g(p);
    g.update(s, mm(x, y, 12.0), kDt);
    const ContactResult c = g.update(s, mm(x, y, kC - 2.0), kDt);  // 2 mm deep
    if (material) *material = c.material;
    return c.force_n.z;
}

TEST(Materials, GodObjectUsesTheTouchedIntervalsMaterial) {
    const auto s = two_materials();
    auto table = std::make_shared<MaterialTable>();
    table->set(7, Material{300.0, 0.0, 0.0, 0.0});
    ContactParams p{700.0, 0.0, 0.0};
    p.materials = table;
    int m = -1;
    // Material 0 (table default 700 N/m, damping 0.5 N*s/m on a 2 mm step in 1 ms: 1.4 + 1.0 N).
    EXPECT_NEAR(pressed_force(*s, p, 10.2, &m), 700.0 * 2e-3 + 0.5 * 2.0, 1e-9);
    EXPECT_EQ(m, 0);
    // Material 7: 300 N/m, no damping.
    EXPECT_NEAR(pressed_force(*s, p, 20.2, &m), 0.6, 1e-9);
    EXPECT_EQ(m, 7);
    // At the border the vertex with the largest barycentric weight decides. On the lattice line y = 10:
    // x = 15.4 -> ray 15 (weight 0.6, material 0), x = 15.6 -> ray 16 (weight 0.6, material 7). At
    // (15.6, 10.3) the triangle (15,10), (16,10), (16,11) weighs 0.4, 0.3, 0.3: ray 15 again.
    pressed_force(*s, p, 15.4, &m, 10.0);
    EXPECT_EQ(m, 0);
    EXPECT_NEAR(pressed_force(*s, p, 15.6, &m, 10.0), 0.6, 1e-9);
    EXPECT_EQ(m, 7);
    pressed_force(*s, p, 15.6, &m, 10.3);
    EXPECT_EQ(m, 0);
    // Without a table, every id uses the ContactParams fields.
    p.materials = nullptr;
    EXPECT_NEAR(pressed_force(*s, p, 20.2, &m), 1.4, 1e-9);
    EXPECT_EQ(m, 7);
}

TEST(Materials, FrictionComesFromTheMaterial) {
    const auto s = two_materials();
    auto table = std::make_shared<MaterialTable>();
    table->set(7, Material{700.0, 0.0, 0.5, 0.5});
    ContactParams p{700.0, 0.0, 0.0};
    p.materials = table;
    // Press 2 mm deep, then drag 0.5 mm along y: material 0 slides freely, material 7 sticks
    // (0.5 mm < mu_s * 2 mm), so its force gains a tangential part of 700 N/m * 0.5 mm.
    for (const double x : {10.2, 20.2}) {
        GodObject g(p);
        g.update(*s, mm(x, 10.3, 12.0), kDt);
        g.update(*s, mm(x, 10.3, kC - 2.0), kDt);
        const ContactResult c = g.update(*s, mm(x, 10.8, kC - 2.0), kDt);
        ASSERT_TRUE(c.contact);
        EXPECT_NEAR(c.force_n.y, x < 16 ? 0.0 : -0.35, 1e-9) << x;
        EXPECT_NEAR(c.force_n.z, 1.4, 1e-9);
    }
}

}  // namespace
}  // namespace tridex::haptics
