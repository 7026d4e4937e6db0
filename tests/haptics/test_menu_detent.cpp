// The pie menu's detent: a restoring force toward the nearest slice centre, zero at centres and borders, faded in
// from the dead radius; slice indices clockwise from 12 o'clock; checked settings.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "haptics/menu_detent.hpp"

namespace tridex::haptics {
namespace {

constexpr double kPi = std::numbers::pi;

// An open 8-slice menu in a tilted plane (right = +y, up = +z, normal = +x), away from the origin.
MenuDetent menu() {
    MenuDetent m;
    m.open = true;
    m.centre_m = Vec3(0.1, -0.2, 0.3);
    m.right = Vec3(0.0, 1.0, 0.0);
    m.up = Vec3(0.0, 0.0, 1.0);
    m.slices = 8;
    m.dead_radius_m = 0.015;
    m.amplitude_n = 0.3;
    return m;
}

// The point at in-plane radius rho (m) and angle theta (rad, from right towards up), `normal_m` off the plane.
Vec3 at(const MenuDetent& m, double rho, double theta, double normal_m = 0.0) {
    return m.centre_m + rho * (std::cos(theta) * m.right + std::sin(theta) * m.up) +
           normal_m * glm::cross(m.right, m.up);
}

// The force's component along increasing theta at that point, N.
double tangential(const MenuDetent& m, double rho, double theta) {
    const Vec3 e_theta = -std::sin(theta) * m.right + std::cos(theta) * m.up;
    return glm::dot(menu_detent_force(m, at(m, rho, theta)), e_theta);
}

double centre_angle(const MenuDetent& m, int k) { return 0.5 * kPi - k * 2.0 * kPi / m.slices; }

TEST(MenuDetent, ZeroAtSliceCentresAndBorders) {
    const MenuDetent m = menu();
    const double half = kPi / m.slices;
    for (int k = 0; k < m.slices; ++k)
        for (double rho : {0.02, 0.03, 0.05}) {
            EXPECT_LT(glm::length(menu_detent_force(m, at(m, rho, centre_angle(m, k)))), 1e-12) << k << " " << rho;
            EXPECT_LT(glm::length(menu_detent_force(m, at(m, rho, centre_angle(m, k) + half))), 1e-12) << k;
        }
}

TEST(MenuDetent, RestoresTowardTheNearestSliceCentreOnBothSides) {
    const MenuDetent m = menu();
    const double half = kPi / m.slices;
    for (int k = 0; k < m.slices; ++k)
        for (double frac : {0.05, 0.3, 0.5, 0.7, 0.95}) {
            // Counter-clockwise of the centre (larger theta): pulled back clockwise, and the reverse.
            EXPECT_LT(tangential(m, 0.04, centre_angle(m, k) + frac * half), 0.0) << k << " " << frac;
            EXPECT_GT(tangential(m, 0.04, centre_angle(m, k) - frac * half), 0.0) << k << " " << frac;
        }
}

TEST(MenuDetent, PeaksAtAmplitudeMidwayBeyondTwiceTheDeadRadius) {
    const MenuDetent m = menu();
    const double quarter = 0.5 * kPi / m.slices;
    for (int k = 0; k < m.slices; ++k)
        for (double rho : {2.0 * m.dead_radius_m, 0.04, 0.2}) {
            EXPECT_NEAR(tangential(m, rho, centre_angle(m, k) + quarter), -m.amplitude_n, 1e-12) << k << " " << rho;
            EXPECT_NEAR(tangential(m, rho, centre_angle(m, k) - quarter), m.amplitude_n, 1e-12) << k << " " << rho;
        }
}

TEST(MenuDetent, FadesInFromTheDeadRadiusAndIsZeroInside) {
    const MenuDetent m = menu();
    const double mid = centre_angle(m, 3) + 0.5 * kPi / m.slices;
    EXPECT_NEAR(tangential(m, 1.5 * m.dead_radius_m, mid), -0.5 * m.amplitude_n, 1e-12);
    EXPECT_NEAR(tangential(m, 1.25 * m.dead_radius_m, mid), -0.25 * m.amplitude_n, 1e-12);
    for (double rho : {0.0, 0.5 * m.dead_radius_m, 0.999 * m.dead_radius_m})
        EXPECT_EQ(menu_detent_force(m, at(m, rho, mid)), Vec3(0.0)) << rho;
    EXPECT_EQ(menu_detent_force(m, m.centre_m), Vec3(0.0));
}

TEST(MenuDetent, IsPurelyTangentialAndIgnoresTheDistanceFromThePlane) {
    const MenuDetent m = menu();
    const double theta = centre_angle(m, 5) + 0.3;
    const Vec3 in_plane = menu_detent_force(m, at(m, 0.04, theta));
    const Vec3 off_plane = menu_detent_force(m, at(m, 0.04, theta, 0.02));
    EXPECT_NEAR(glm::length(off_plane - in_plane), 0.0, 1e-12);
    const Vec3 radial = std::cos(theta) * m.right + std::sin(theta) * m.up;
    EXPECT_NEAR(glm::dot(in_plane, radial), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(in_plane, glm::cross(m.right, m.up)), 0.0, 1e-12);
    EXPECT_GT(glm::length(in_plane), 0.0);
}

TEST(MenuDetent, TangentialStiffnessAtASliceCentreIsAmplitudeTimesSlicesOverRho) {
    const MenuDetent m = menu();
    for (double rho : {0.03, 0.06}) {
        const double h = 1e-6;  // rad
        const double theta = centre_angle(m, 2);
        const double slope = (tangential(m, rho, theta + h) - tangential(m, rho, theta - h)) / (2.0 * h * rho);  // N/m
        EXPECT_NEAR(slope, -m.amplitude_n * m.slices / rho, 1e-4 * m.amplitude_n * m.slices / rho) << rho;
    }
}

TEST(MenuDetent, ClosedNonFiniteOrBadSettingsGiveNoForceAndNoSlice) {
    MenuDetent m = menu();
    const Vec3 p = at(m, 0.04, 0.3);
    ASSERT_NE(menu_detent_force(m, p), Vec3(0.0));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(menu_detent_force(m, Vec3(nan, 0.0, 0.0)), Vec3(0.0));
    EXPECT_EQ(menu_detent_force(m, Vec3(0.0, std::numeric_limits<double>::infinity(), 0.0)), Vec3(0.0));
    EXPECT_EQ(menu_detent_slice(m, Vec3(nan)), -1);
    m.open = false;
    EXPECT_EQ(menu_detent_force(m, p), Vec3(0.0));
    EXPECT_EQ(menu_detent_slice(m, p), -1);
    m = menu();
    m.slices = 0;
    EXPECT_EQ(menu_detent_force(m, p), Vec3(0.0));
    EXPECT_EQ(menu_detent_slice(m, p), -1);
    m = menu();
    m.up = m.right;
    EXPECT_EQ(menu_detent_force(m, p), Vec3(0.0));
    m = menu();
    m.dead_radius_m = nan;
    EXPECT_EQ(menu_detent_force(m, p), Vec3(0.0));
    m = menu();
    m.amplitude_n = 0.0;
    EXPECT_EQ(menu_detent_force(m, p), Vec3(0.0));
    EXPECT_GE(menu_detent_slice(m, p), 0);  // no force, but the slice is still picked
}

TEST(MenuDetent, EightSlicesAtTheCompassDirectionsGoClockwiseFromTwelve) {
    const MenuDetent m = menu();
    // N, NE, E, SE, S, SW, W, NW as angles from right towards up.
    const double compass[8] = {0.5 * kPi, 0.25 * kPi, 0.0, -0.25 * kPi, -0.5 * kPi, -0.75 * kPi, kPi, 0.75 * kPi};
    for (int k = 0; k < 8; ++k) {
        EXPECT_EQ(menu_detent_slice(m, at(m, 0.05, compass[k])), k) << k;
        // Anywhere within the slice (off the plane too), short of its borders.
        EXPECT_EQ(menu_detent_slice(m, at(m, 0.02, compass[k] + 0.9 * kPi / 8, 0.01)), k) << k;
        EXPECT_EQ(menu_detent_slice(m, at(m, 0.02, compass[k] - 0.9 * kPi / 8)), k) << k;
    }
    EXPECT_EQ(menu_detent_slice(m, at(m, 0.5 * m.dead_radius_m, 0.0)), -1);
    EXPECT_EQ(menu_detent_slice(m, at(m, 0.999 * m.dead_radius_m, 0.0)), -1);
    EXPECT_EQ(menu_detent_slice(m, m.centre_m), -1);
}

TEST(MenuDetent, OtherSliceCounts) {
    MenuDetent m = menu();
    m.slices = 1;
    for (double theta : {0.0, 1.0, 2.0, -2.5}) EXPECT_EQ(menu_detent_slice(m, at(m, 0.05, theta)), 0) << theta;
    m.slices = 4;  // N, E, S, W
    EXPECT_EQ(menu_detent_slice(m, at(m, 0.05, 0.5 * kPi)), 0);
    EXPECT_EQ(menu_detent_slice(m, at(m, 0.05, 0.0)), 1);
    EXPECT_EQ(menu_detent_slice(m, at(m, 0.05, -0.5 * kPi)), 2);
    EXPECT_EQ(menu_detent_slice(m, at(m, 0.05, kPi)), 3);
    EXPECT_EQ(menu_detent_slice(m, at(m, 0.05, 0.5 * kPi + 0.7)), 0);  // just counter-clockwise of 12: still 0
    m.slices = 32;
    for (int k = 0; k < 32; ++k) EXPECT_EQ(menu_detent_slice(m, at(m, 0.05, centre_angle(m, k))), k) << k;
}

// The message of the tridex::Error that check_menu_detent throws, or "" when it accepts.
std::string refusal(const MenuDetent& m, double cap = std::numeric_limits<double>::infinity()) {
    try {
        check_menu_detent(m, cap);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(MenuDetent, CheckNamesTheFieldAtFault) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(refusal(menu()), "");
    EXPECT_EQ(refusal(MenuDetent{}, 700.0), "");  // the defaults: 0.3 * 8 / 0.015 = 160 N/m
    struct Case {
        void (*edit)(MenuDetent&);
        const char* field;
    };
    const Case cases[] = {
        {[](MenuDetent& m) { m.centre_m.y = std::numeric_limits<double>::infinity(); }, "MenuDetent.centre_m"},
        {[](MenuDetent& m) { m.right = Vec3(2.0, 0.0, 0.0); }, "MenuDetent.right"},
        {[](MenuDetent& m) { m.right.x = std::numeric_limits<double>::quiet_NaN(); }, "MenuDetent.right"},
        {[](MenuDetent& m) { m.up = Vec3(0.0); }, "MenuDetent.up"},
        {[](MenuDetent& m) { m.up = glm::normalize(Vec3(0.0, 1.0, 1.0)); }, "MenuDetent.up"},  // not orthogonal
        {[](MenuDetent& m) { m.slices = 0; }, "MenuDetent.slices"},
        {[](MenuDetent& m) { m.slices = 33; }, "MenuDetent.slices"},
        {[](MenuDetent& m) { m.dead_radius_m = 0.0; }, "MenuDetent.dead_radius_m"},
        {[](MenuDetent& m) { m.dead_radius_m = -0.01; }, "MenuDetent.dead_radius_m"},
        {[](MenuDetent& m) { m.amplitude_n = -0.1; }, "MenuDetent.amplitude_n"},
        {[](MenuDetent& m) { m.amplitude_n = std::numeric_limits<double>::infinity(); }, "MenuDetent.amplitude_n"},
    };
    for (const Case& c : cases) {
        MenuDetent m = menu();
        c.edit(m);
        const std::string why = refusal(m);
        EXPECT_NE(why.find(c.field), std::string::npos) << c.field << ": " << why;
        m.open = false;  // a closed menu's settings are checked all the same
        EXPECT_NE(refusal(m).find(c.field), std::string::npos) << c.field;
    }
    EXPECT_NE(refusal(menu(), 0.0).find("max_stiffness_n_per_m"), std::string::npos);
    EXPECT_NE(refusal(menu(), nan).find("max_stiffness_n_per_m"), std::string::npos);
}

TEST(MenuDetent, CheckRefusesADetentStifferThanTheCapAtTheDeadRadius) {
    MenuDetent m = menu();  // 0.3 N * 8 / 0.015 m = 160 N/m
    EXPECT_EQ(refusal(m, 160.0 * (1.0 + 1e-12)), "");
    const std::string why = refusal(m, 150.0);
    EXPECT_NE(why.find("MenuDetent.amplitude_n"), std::string::npos) << why;
    EXPECT_NE(why.find("160"), std::string::npos) << why;
    m.dead_radius_m = 0.03;  // 80 N/m
    EXPECT_EQ(refusal(m, 150.0), "");
    m.slices = 16;  // 160 N/m again
    EXPECT_NE(refusal(m, 150.0), "");
}

}  // namespace
}  // namespace tridex::haptics
