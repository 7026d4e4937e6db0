// compute/contour_dual.cpp - the tile cache of the contourer and the assembly of the global mesh.
#include "compute/contour_dual.hpp"

#include <algorithm>
#include <string>
#include <sstream>

#include "core/error.hpp"

namespace tridex::compute {

Contourer::Contourer(const TriDexel& model) : lattice_(model.lattice), tiles_(model.tiles.tiles) {
    for (int a = 0; a < 3; ++a) {
        codec_.nodes[a] = lattice_.cells[a] + 1;
        codec_.tiles[a] = tiles_[a];
    }
    tile_meshes_.resize(static_cast<std::size_t>(tiles_[0]) * tiles_[1] * tiles_[2]);
}

void Contourer::check_model(const TriDexel& model) const {
    const Lattice& l = model.lattice;
    if (l.cells != lattice_.cells || l.cell_m != lattice_.cell_m || l.origin_m != lattice_.origin_m ||
        model.tiles.tiles != tiles_ || model.tiles.count() != tile_meshes_.size()) {
        std::ostringstream msg;
        msg << "contour: model lattice " << l.cells[0] << "x" << l.cells[1] << "x" << l.cells[2]
            << " differs from the lattice " << lattice_.cells[0] << "x" << lattice_.cells[1] << "x"
            << lattice_.cells[2] << " this Contourer was built for";
        throw Error(msg.str());
    }
    for (int a = 0; a < 3; ++a) {
        const RaySet& s = model.sets[a];
        if (s.axis != a || s.nu != l.nodes((a + 1) % 3) || s.nv != l.nodes((a + 2) % 3) ||
            s.rays.size() != static_cast<std::size_t>(s.nu) * static_cast<std::size_t>(s.nv))
            throw Error("contour: model ray set " + std::to_string(a) + " does not match its lattice");
    }
}

std::size_t Contourer::update(TriDexel& model) {
    check_model(model);
    std::size_t redone = 0, cells = 0;
    for (int tz = 0; tz < tiles_[2]; ++tz)
        for (int ty = 0; ty < tiles_[1]; ++ty)
            for (int tx = 0; tx < tiles_[0]; ++tx) {
                const std::size_t idx = model.tiles.index(tx, ty, tz);
                if (!model.tiles.dirty[idx]) continue;
                worker_.run(model, {tx, ty, tz}, tile_meshes_[idx]);
                cells += tile_meshes_[idx].cells_visited;
                ++redone;
            }
    model.clear_dirty();
    last_tiles_ = redone;
    last_cells_ = cells;
    return redone;
}

TriMesh Contourer::mesh() const {
    TriMesh m;
    std::vector<std::size_t> offset(tile_meshes_.size() + 1, 0);
    std::size_t tris = 0;
    for (std::size_t t = 0; t < tile_meshes_.size(); ++t) {
        offset[t + 1] = offset[t] + tile_meshes_[t].keys.size();
        tris += tile_meshes_[t].triangles.size();
    }
    m.positions.reserve(offset.back());
    for (const contour::TileMesh& tm : tile_meshes_)
        for (const Vec3& g : tm.grid) m.positions.push_back(lattice_.to_world(g));
    m.triangles.reserve(tris);
    auto index_of = [&](contour::VertexKey key) {
        const std::size_t t = codec_.owner_tile(key);
        const auto& keys = tile_meshes_[t].keys;
        const auto it = std::lower_bound(keys.begin(), keys.end(), key);
        if (it == keys.end() || *it != key)
            throw Error("contour: tile " + std::to_string(t) +
                        " lacks a vertex its neighbour needs; the model changed without mark_dirty() covering the change");
        return static_cast<std::uint32_t>(offset[t] + static_cast<std::size_t>(it - keys.begin()));
    };
    std::vector<std::uint32_t> foreign_index;
    for (std::size_t t = 0; t < tile_meshes_.size(); ++t) {
        const contour::TileMesh& tm = tile_meshes_[t];
        foreign_index.clear();
        for (const contour::VertexKey key : tm.foreign) foreign_index.push_back(index_of(key));
        const auto base = static_cast<std::uint32_t>(offset[t]);
        for (const auto& tri : tm.triangles) {
            std::array<std::uint32_t, 3> g{};
            for (int v = 0; v < 3; ++v)
                g[v] = tri[v] < contour::TileMesh::kForeign ? base + tri[v] : foreign_index[tri[v] - contour::TileMesh::kForeign];
            m.triangles.push_back(g);
        }
    }
    return m;
}

ContourStats Contourer::stats() const {
    ContourStats s;
    s.tiles = tile_meshes_.size();
    s.tiles_recontoured = last_tiles_;
    s.cells_visited = last_cells_;
    for (const contour::TileMesh& tm : tile_meshes_) {
        s.vertices += tm.keys.size();
        s.triangles += tm.triangles.size();
        s.fallbacks += tm.fallbacks;
        s.split_faces += tm.split_faces;
    }
    return s;
}

}  // namespace tridex::compute
