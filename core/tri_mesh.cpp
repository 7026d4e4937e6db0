// core/tri_mesh.cpp - topology checks and integrals of TriMesh.
#include "core/tri_mesh.hpp"

#include <algorithm>

namespace tridex {

Aabb TriMesh::bounds() const {
    Aabb box;
    for (const Vec3& p : positions) box.add(p);
    return box;
}

EdgeStats edge_stats(const TriMesh& mesh) {
    // Directed half-edges (from, to) sorted by their undirected key; count uses per key.
    struct HalfEdge {
        std::uint64_t key;  // min << 32 | max
        bool forward;       // from < to
    };
    EdgeStats stats;
    std::vector<HalfEdge> half;
    half.reserve(mesh.triangles.size() * 3);
    for (const auto& t : mesh.triangles) {
        if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
            ++stats.degenerate_triangles;
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            const std::uint64_t lo = std::min(a, b), hi = std::max(a, b);
            half.push_back({(lo << 32) | hi, a < b});
        }
    }
    std::sort(half.begin(), half.end(), [](const HalfEdge& x, const HalfEdge& y) { return x.key < y.key; });
    for (std::size_t i = 0; i < half.size();) {
        std::size_t j = i;
        int forward = 0;
        while (j < half.size() && half[j].key == half[i].key) forward += half[j++].forward ? 1 : 0;
        const std::size_t uses = j - i;
        ++stats.edges;
        if (uses == 1) ++stats.boundary_edges;
        else if (uses > 2) ++stats.nonmanifold_edges;
        else if (forward != 1) ++stats.misoriented_edges;
        i = j;
    }
    return stats;
}

std::size_t mesh_components(const TriMesh& mesh) {
    std::vector<std::uint32_t> parent(mesh.positions.size());
    for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<std::uint32_t>(i);
    const auto find = [&](std::uint32_t a) {
        while (parent[a] != a) a = parent[a] = parent[parent[a]];
        return a;
    };
    for (const auto& t : mesh.triangles)
        for (int k = 1; k < 3; ++k) {
            const std::uint32_t a = find(t[0]), b = find(t[k]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    std::vector<std::uint8_t> seen(parent.size(), 0);
    std::size_t n = 0;
    for (const auto& t : mesh.triangles) {
        const std::uint32_t r = find(t[0]);
        if (!seen[r]) {
            seen[r] = 1;
            ++n;
        }
    }
    return n;
}

double signed_volume(const TriMesh& mesh) {
    double six_v = 0.0;
    for (const auto& t : mesh.triangles) {
        const Vec3& a = mesh.positions[t[0]];
        const Vec3& b = mesh.positions[t[1]];
        const Vec3& c = mesh.positions[t[2]];
        six_v += glm::dot(a, glm::cross(b, c));
    }
    return six_v / 6.0;
}

std::vector<Vec3> vertex_normals(const TriMesh& mesh) {
    std::vector<Vec3> n(mesh.positions.size(), Vec3(0.0));
    for (const auto& t : mesh.triangles) {
        const Vec3& a = mesh.positions[t[0]];
        const Vec3 fn = glm::cross(mesh.positions[t[1]] - a, mesh.positions[t[2]] - a);  // 2 * area * normal
        for (int k = 0; k < 3; ++k) n[t[k]] += fn;
    }
    for (Vec3& v : n) {
        const double len = glm::length(v);
        v = len > 0.0 ? v / len : Vec3(0.0);
    }
    return n;
}

}  // namespace tridex
