// core/primitives.cpp - box and icosphere meshes.
#include "core/primitives.hpp"

#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "core/error.hpp"

namespace tridex {

TriMesh box_mesh(const Aabb& box) {
    const Vec3 s = box.size();
    if (box.empty() || !is_finite(box.lo) || !is_finite(box.hi) || !(s.x > 0.0 && s.y > 0.0 && s.z > 0.0))
        throw Error("box_mesh: box is empty, flat or not finite");
    TriMesh m;
    for (int i = 0; i < 8; ++i)  // corner i: bit 0 -> x, bit 1 -> y, bit 2 -> z
        m.positions.push_back(Vec3(i & 1 ? box.hi.x : box.lo.x, i & 2 ? box.hi.y : box.lo.y, i & 4 ? box.hi.z : box.lo.z));
    // Each face as a counter-clockwise quad seen from outside.
    const std::uint32_t quads[6][4] = {
        {0, 4, 6, 2},  // -x
        {1, 3, 7, 5},  // +x
        {0, 1, 5, 4},  // -y
        {2, 6, 7, 3},  // +y
        {0, 2, 3, 1},  // -z
        {4, 5, 7, 6},  // +z
    };
    for (const auto& q : quads) {
        m.triangles.push_back({q[0], q[1], q[2]});
        m.triangles.push_back({q[0], q[2], q[3]});
    }
    return m;
}

TriMesh icosphere_mesh(const Vec3& centre_m, double radius_m, int subdivisions) {
    if (!std::isfinite(radius_m) || !(radius_m > 0.0)) throw Error("icosphere_mesh: radius must be > 0");
    if (!is_finite(centre_m)) throw Error("icosphere_mesh: centre is not finite");
    if (subdivisions < 0 || subdivisions > 7)
        throw Error("icosphere_mesh: subdivisions must be in [0, 7], got " + std::to_string(subdivisions));
    const double p = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vec3> dir = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0}, {0, -1, p}, {0, 1, p},
                             {0, -1, -p}, {0, 1, -p}, {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
    for (Vec3& d : dir) d = glm::normalize(d);
    std::vector<std::array<std::uint32_t, 3>> tris = {
        {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
        {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            auto [it, fresh] = mid.try_emplace(key, static_cast<std::uint32_t>(dir.size()));
            if (fresh) dir.push_back(glm::normalize(dir[a] + dir[b]));
            return it->second;
        };
        std::vector<std::array<std::uint32_t, 3>> next;
        next.reserve(tris.size() * 4);
        for (const auto& t : tris) {
            const std::uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
            next.push_back({t[0], ab, ca});
            next.push_back({t[1], bc, ab});
            next.push_back({t[2], ca, bc});
            next.push_back({ab, bc, ca});
        }
        tris = std::move(next);
    }
    TriMesh m;
    m.positions.reserve(dir.size());
    for (const Vec3& d : dir) m.positions.push_back(centre_m + radius_m * d);
    m.triangles = std::move(tris);
    return m;
}

}  // namespace tridex
