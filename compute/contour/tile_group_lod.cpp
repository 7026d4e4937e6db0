// compute/contour/tile_group_lod.cpp - merged tile meshes simplified as one group.
#include "compute/contour/tile_group_lod.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <unordered_map>

#include "core/error.hpp"

namespace tridex::compute {
namespace {

struct PositionKey {
    std::array<std::uint64_t, 3> bits;
    bool operator==(const PositionKey&) const = default;
};

struct PositionHash {
    std::size_t operator()(const PositionKey& k) const {
        std::uint64_t h = 1469598103934665603ull;
        for (const std::uint64_t b : k.bits) h = (h ^ b) * 1099511628211ull;
        return static_cast<std::size_t>(h ^ (h >> 29));
    }
};

PositionKey key_of(const Vec3& p) {
    PositionKey k{};
    for (int a = 0; a < 3; ++a) {
        const double c = p[a] == 0.0 ? 0.0 : p[a];  // -0 and +0 weld
        std::memcpy(&k.bits[a], &c, sizeof c);
    }
    return k;
}

}  // namespace

TriMesh merge_lod_parts(std::span<const LodPart> parts, std::vector<std::uint8_t>& materials, std::vector<Vec3>& normals) {
    TriMesh out;
    materials.clear();
    normals.clear();
    struct BorderVertex {
        std::uint32_t index;  // merged vertex
        std::size_t part;     // the part that made it
    };
    std::unordered_map<PositionKey, BorderVertex, PositionHash> index;
    std::vector<Vec3> sums;
    std::vector<std::uint32_t> remap;
    for (std::size_t p = 0; p < parts.size(); ++p) {
        const LodPart& part = parts[p];
        if (!part.mesh || part.mesh->triangles.empty()) continue;
        const TriMesh& m = *part.mesh;
        const std::size_t nv = m.positions.size();
        if (!part.materials.empty() && part.materials.size() != nv)
            throw Error("merge_lod_parts: part " + std::to_string(p) + " has " + std::to_string(part.materials.size()) +
                        " materials for " + std::to_string(nv) + " vertices");
        if (!part.normals.empty() && part.normals.size() != nv)
            throw Error("merge_lod_parts: part " + std::to_string(p) + " has " + std::to_string(part.normals.size()) +
                        " normals for " + std::to_string(nv) + " vertices");
        const std::vector<Vec3> own = part.normals.empty() ? vertex_normals(m) : std::vector<Vec3>{};
        const std::span<const Vec3> nrm = part.normals.empty() ? std::span<const Vec3>(own) : part.normals;
        // Only the part's open-border vertices can be shared with another part; inside a part, vertices at one
        // position (a split cell's) stay distinct.
        std::vector<std::uint8_t> on_border(nv, 0);
        {
            std::unordered_map<std::uint64_t, int> directed;
            const auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t{a} << 32) | b; };
            for (const auto& t : m.triangles)
                for (int k = 0; k < 3; ++k) {
                    if (t[k] >= nv)
                        throw Error("merge_lod_parts: part " + std::to_string(p) + " has a vertex index out of range");
                    ++directed[key(t[k], t[(k + 1) % 3])];
                }
            for (const auto& t : m.triangles)
                for (int k = 0; k < 3; ++k)
                    if (!directed.count(key(t[(k + 1) % 3], t[k]))) on_border[t[k]] = on_border[t[(k + 1) % 3]] = 1;
        }
        remap.assign(nv, 0);
        for (std::size_t v = 0; v < nv; ++v) {
            const auto fresh_vertex = [&] {
                out.positions.push_back(m.positions[v]);
                materials.push_back(part.materials.empty() ? 0 : part.materials[v]);
                sums.push_back(Vec3(0.0));
                return static_cast<std::uint32_t>(out.positions.size() - 1);
            };
            std::uint32_t at = 0;
            if (on_border[v]) {
                const auto [it, fresh] = index.try_emplace(key_of(m.positions[v]), BorderVertex{0, p});
                if (fresh || it->second.part == p) {
                    at = fresh_vertex();
                    if (fresh) it->second.index = at;
                } else {
                    at = it->second.index;
                }
            } else {
                at = fresh_vertex();
            }
            sums[at] += nrm[v];
            remap[v] = at;
        }
        for (std::size_t t = 0; t < m.triangles.size(); ++t) {
            std::array<std::uint32_t, 3> tri{};
            for (int k = 0; k < 3; ++k) {
                if (m.triangles[t][k] >= nv)
                    throw Error("merge_lod_parts: part " + std::to_string(p) + " triangle " + std::to_string(t) +
                                " has a vertex index out of range");
                tri[k] = remap[m.triangles[t][k]];
            }
            out.triangles.push_back(tri);
        }
    }
    normals.resize(sums.size());
    for (std::size_t v = 0; v < sums.size(); ++v) {
        const double len = glm::length(sums[v]);
        normals[v] = len > 0.0 ? sums[v] / len : Vec3(0.0, 0.0, 1.0);
    }
    return out;
}

std::vector<TileLodLevel> build_group_lod(std::span<const LodPart> parts, const TileLodOptions& options) {
    std::vector<std::uint8_t> materials;
    std::vector<Vec3> normals;
    const TriMesh merged = merge_lod_parts(parts, materials, normals);
    double base = 0.0;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const LodPart& p = parts[i];
        if (!std::isfinite(p.error_m) || p.error_m < 0.0)
            throw Error("build_group_lod: part " + std::to_string(i) + " has error_m " + std::to_string(p.error_m) +
                        " (must be finite and >= 0)");
        if (p.mesh && !p.mesh->triangles.empty()) base = std::max(base, p.error_m);
    }
    if (merged.triangles.empty()) return {};
    return build_lod_levels(merged, materials, normals, base, options);
}

}  // namespace tridex::compute
