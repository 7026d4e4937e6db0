// haptics/mesh_tool_points.cpp - area-weighted low-discrepancy samples and farthest-point sampling on a tool mesh.
#include "haptics/mesh_tool_points.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace tridex::haptics {

namespace {

/// Radical inverse of i in `base`: the van der Corput / Halton sequence, in [0, 1).
double radical_inverse(std::uint32_t i, std::uint32_t base) {
    double inv = 1.0 / base, f = inv, r = 0.0;
    while (i > 0) {
        r += f * (i % base);
        i /= base;
        f *= inv;
    }
    return r;
}

}  // namespace

ToolPoints mesh_surface_points(const TriMesh& mesh_m, int count) {
    if (count < 1 || count > kMaxToolPoints)
        throw Error("mesh_surface_points: count = " + std::to_string(count) + " must be in [1, " +
                    std::to_string(kMaxToolPoints) + "]");
    for (const Vec3& p : mesh_m.positions)
        if (!is_finite(p)) throw Error("mesh_surface_points: a vertex position is not finite");
    for (const auto& t : mesh_m.triangles)
        for (const std::uint32_t i : t)
            if (i >= mesh_m.positions.size()) throw Error("mesh_surface_points: a triangle index is out of range");
    std::vector<double> cumulative;  // cumulative triangle areas
    cumulative.reserve(mesh_m.triangles.size());
    double total = 0.0;
    for (const auto& t : mesh_m.triangles) {
        const Vec3 &a = mesh_m.positions[t[0]], &b = mesh_m.positions[t[1]], &c = mesh_m.positions[t[2]];
        total += 0.5 * glm::length(glm::cross(b - a, c - a));
        cumulative.push_back(total);
    }
    if (!(total > 0.0) || !std::isfinite(total)) throw Error("mesh_surface_points: the mesh has no surface area");

    std::vector<Vec3> at, normal;
    at.reserve(kMeshPointCandidates + 1);
    normal.reserve(kMeshPointCandidates + 1);
    // The tip first: the vertex lowest along the tool axis (-y), ties to the lowest index.
    const std::vector<Vec3> vn = vertex_normals(mesh_m);
    std::size_t tip = 0;
    for (std::size_t i = 1; i < mesh_m.positions.size(); ++i)
        if (mesh_m.positions[i].y < mesh_m.positions[tip].y) tip = i;
    at.push_back(mesh_m.positions[tip]);
    normal.push_back(glm::length(vn[tip]) > 0.0 ? vn[tip] : Vec3(0.0, -1.0, 0.0));
    for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(kMeshPointCandidates); ++i) {
        const double pick = (radical_inverse(i, 2) + 0.5 / kMeshPointCandidates) * total;
        const std::size_t t = std::min<std::size_t>(
            static_cast<std::size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin()),
            cumulative.size() - 1);
        const auto& tri = mesh_m.triangles[t];
        const Vec3 &a = mesh_m.positions[tri[0]], &b = mesh_m.positions[tri[1]], &c = mesh_m.positions[tri[2]];
        const Vec3 n = glm::cross(b - a, c - a);
        if (!(glm::length(n) > 0.0)) continue;  // zero-area triangles carry no samples
        const double s = std::sqrt(radical_inverse(i, 3)), r = radical_inverse(i, 5);
        at.push_back(a * (1.0 - s) + b * (s * (1.0 - r)) + c * (s * r));
        normal.push_back(glm::normalize(n));
    }
    // Farthest-point sampling: each next point is the candidate farthest from those chosen.
    ToolPoints p;
    std::vector<double> d2(at.size(), std::numeric_limits<double>::infinity());
    std::size_t next = 0;
    for (int k = 0; k < count; ++k) {
        p.local_m[k] = at[next];
        p.normal[k] = normal[next];
        p.count = k + 1;
        std::size_t far = 0;
        for (std::size_t i = 0; i < at.size(); ++i) {
            const Vec3 d = at[i] - at[next];
            d2[i] = std::min(d2[i], glm::dot(d, d));
            if (d2[i] > d2[far]) far = i;
        }
        next = far;
    }
    return p;
}

}  // namespace tridex::haptics
