// renderer/scene/primitive_meshes.cpp - UV sphere and box triangulations.
#include "renderer/scene/primitive_meshes.hpp"

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

}  // namespace tridex::renderer
