// renderer/primitive_meshes.cpp - UV sphere and box triangulations.
#include "renderer/primitive_meshes.hpp"

#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace tridex::renderer {

TriMesh unit_sphere(int rings, int segments) {
    if (rings < 2 || segments < 3)
        throw Error("unit_sphere: need rings >= 2 and segments >= 3 (got " + std::to_string(rings) + ", " +
                    std::to_string(segments) + ")");
    TriMesh m;
    // Vertex 0 = north pole (+y), then rings-1 latitude circles, then the south pole.
    m.positions.push_back(Vec3(0.0, 1.0, 0.0));
    for (int i = 1; i < rings; ++i) {
        const double theta = std::numbers::pi * i / rings;  // from +y
        for (int j = 0; j < segments; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / segments;
            m.positions.push_back(Vec3(std::sin(theta) * std::sin(phi), std::cos(theta), std::sin(theta) * std::cos(phi)));
        }
    }
    const auto south = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back(Vec3(0.0, -1.0, 0.0));
    const auto ring = [&](int i, int j) { return static_cast<std::uint32_t>(1 + (i - 1) * segments + (j % segments)); };
    // phi grows from +z towards +x; seen from outside, counter-clockwise is (north, j, j+1) going down.
    for (int j = 0; j < segments; ++j) m.triangles.push_back({0u, ring(1, j), ring(1, j + 1)});
    for (int i = 1; i + 1 < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
            m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
        }
    for (int j = 0; j < segments; ++j) m.triangles.push_back({south, ring(rings - 1, j + 1), ring(rings - 1, j)});
    return m;
}

TriMesh box_mesh(const Aabb& box) {
    if (box.empty()) throw Error("box_mesh: the box is empty");
    TriMesh m;
    for (int k = 0; k < 8; ++k)  // corner k: bit 0 -> x, bit 1 -> y, bit 2 -> z
        m.positions.push_back(Vec3(k & 1 ? box.hi.x : box.lo.x, k & 2 ? box.hi.y : box.lo.y, k & 4 ? box.hi.z : box.lo.z));
    // Each face as a quad (a, b, c, d) counter-clockwise seen from outside.
    const std::uint32_t faces[6][4] = {
        {0, 4, 6, 2},  // -x
        {1, 3, 7, 5},  // +x
        {0, 1, 5, 4},  // -y
        {2, 6, 7, 3},  // +y
        {0, 2, 3, 1},  // -z
        {4, 5, 7, 6},  // +z
    };
    for (const auto& f : faces) {
        m.triangles.push_back({f[0], f[1], f[2]});
        m.triangles.push_back({f[0], f[2], f[3]});
    }
    return m;
}

}  // namespace tridex::renderer
