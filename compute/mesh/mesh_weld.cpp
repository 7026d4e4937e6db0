// compute/mesh/mesh_weld.cpp - exact vertex welding and the closed-manifold check.
#include "compute/mesh/mesh_weld.hpp"

#include <cstring>
#include <unordered_map>
#include <utility>

#include "core/error.hpp"

namespace tridex::compute {
namespace {

struct Key {
    std::uint64_t bits[3];
    bool operator==(const Key& o) const { return bits[0] == o.bits[0] && bits[1] == o.bits[1] && bits[2] == o.bits[2]; }
};

struct KeyHash {
    std::size_t operator()(const Key& k) const {
        std::uint64_t h = 0x9e3779b97f4a7c15ull;
        for (std::uint64_t b : k.bits) {
            h ^= b + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
            h *= 0xff51afd7ed558ccdull;
        }
        return static_cast<std::size_t>(h ^ (h >> 33));
    }
};

Key key_of(const Vec3& p) {
    Key k;
    for (int a = 0; a < 3; ++a) {
        const double v = p[a] + 0.0;  // -0.0 + 0.0 == +0.0, so both zeros share one key
        std::memcpy(&k.bits[a], &v, sizeof v);
    }
    return k;
}

}  // namespace

TriMesh weld_exact(const TriMesh& soup, std::vector<std::uint32_t>* source) {
    TriMesh out;
    std::vector<std::uint32_t> first;  // per out vertex: the soup vertex it was made from
    std::unordered_map<Key, std::uint32_t, KeyHash> index;
    index.reserve(soup.positions.size());
    std::vector<std::uint32_t> remap(soup.positions.size(), 0);
    std::vector<bool> seen(soup.positions.size(), false);
    out.triangles.reserve(soup.triangles.size());
    auto id = [&](std::uint32_t v) {
        if (!seen[v]) {
            auto [it, fresh] = index.try_emplace(key_of(soup.positions[v]), static_cast<std::uint32_t>(out.positions.size()));
            if (fresh) {
                out.positions.push_back(soup.positions[v]);
                first.push_back(v);
            }
            remap[v] = it->second;
            seen[v] = true;
        }
        return remap[v];
    };
    for (const auto& t : soup.triangles) {
        const std::array<std::uint32_t, 3> w{id(t[0]), id(t[1]), id(t[2])};
        if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) continue;
        out.triangles.push_back(w);
    }
    // Vertices only used by dropped triangles are still in `out.positions`; remove them.
    std::vector<std::uint32_t> used(out.positions.size(), 0xffffffffu);
    TriMesh compact;
    compact.triangles.reserve(out.triangles.size());
    if (source) source->clear();
    for (auto t : out.triangles) {
        for (auto& v : t) {
            if (used[v] == 0xffffffffu) {
                used[v] = static_cast<std::uint32_t>(compact.positions.size());
                compact.positions.push_back(out.positions[v]);
                if (source) source->push_back(first[v]);
            }
            v = used[v];
        }
        compact.triangles.push_back(t);
    }
    return compact;
}

void require_closed_outward(TriMesh& mesh, const std::string& name) {
    if (mesh.triangles.empty()) throw Error(name + ": no triangles");
    const EdgeStats s = edge_stats(mesh);
    if (s.boundary_edges > 0) {
        std::string msg = name + ": mesh is not closed: " + std::to_string(s.boundary_edges) + " boundary edges";
        if (s.nonmanifold_edges > 0) msg += ", " + std::to_string(s.nonmanifold_edges) + " non-manifold edges";
        throw Error(msg);
    }
    if (s.nonmanifold_edges > 0)
        throw Error(name + ": mesh is not a 2-manifold: " + std::to_string(s.nonmanifold_edges) +
                    " non-manifold edges (used by 3 or more triangles)");
    if (s.misoriented_edges > 0)
        throw Error(name + ": mesh is not consistently oriented: " + std::to_string(s.misoriented_edges) +
                    " edges are used twice in the same direction");
    const double v = signed_volume(mesh);
    if (!(v != 0.0) || !std::isfinite(v)) throw Error(name + ": closed mesh encloses no volume");
    if (v < 0.0)
        for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
}

}  // namespace tridex::compute
