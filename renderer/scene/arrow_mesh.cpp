// renderer/scene/arrow_mesh.cpp - cylinder and cone triangulations.
#include "renderer/scene/arrow_mesh.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "core/error.hpp"

namespace tridex::renderer {
namespace {

void check_segments(const char* what, int segments) {
    if (segments < 3) throw Error(std::string(what) + ": need segments >= 3 (got " + std::to_string(segments) + ")");
}

Vec3 rim(int j, int segments, double z) {
    const double phi = 2.0 * std::numbers::pi * j / segments;
    return Vec3(std::cos(phi), std::sin(phi), z);
}

// A disk of radius 1 in plane z facing +z (up = true) or -z, as a fan around its centre.
void add_cap(TriMesh& m, int segments, double z, bool up) {
    const auto centre = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back(Vec3(0.0, 0.0, z));
    for (int j = 0; j < segments; ++j) m.positions.push_back(rim(j, segments, z));
    for (int j = 0; j < segments; ++j) {
        const std::uint32_t a = centre + 1 + static_cast<std::uint32_t>(j);
        const std::uint32_t b = centre + 1 + static_cast<std::uint32_t>((j + 1) % segments);
        // phi grows counter-clockwise seen from +z.
        m.triangles.push_back(up ? std::array<std::uint32_t, 3>{centre, a, b} : std::array<std::uint32_t, 3>{centre, b, a});
    }
}

}  // namespace

TriMesh unit_cylinder(int segments) {
    check_segments("unit_cylinder", segments);
    TriMesh m;
    for (int j = 0; j < segments; ++j) {
        m.positions.push_back(rim(j, segments, 0.0));
        m.positions.push_back(rim(j, segments, 1.0));
    }
    for (int j = 0; j < segments; ++j) {
        const auto b0 = static_cast<std::uint32_t>(2 * j), t0 = b0 + 1;
        const auto b1 = static_cast<std::uint32_t>(2 * ((j + 1) % segments)), t1 = b1 + 1;
        m.triangles.push_back({b0, b1, t1});
        m.triangles.push_back({b0, t1, t0});
    }
    add_cap(m, segments, 0.0, false);
    add_cap(m, segments, 1.0, true);
    return m;
}

TriMesh unit_cone(int segments) {
    check_segments("unit_cone", segments);
    TriMesh m;
    for (int j = 0; j < segments; ++j) m.positions.push_back(rim(j, segments, 0.0));
    for (int j = 0; j < segments; ++j) m.positions.push_back(Vec3(0.0, 0.0, 1.0));
    for (int j = 0; j < segments; ++j) {
        const auto a = static_cast<std::uint32_t>(j), b = static_cast<std::uint32_t>((j + 1) % segments);
        m.triangles.push_back({a, b, static_cast<std::uint32_t>(segments + j)});
    }
    add_cap(m, segments, 0.0, false);
    return m;
}

}  // namespace tridex::renderer
