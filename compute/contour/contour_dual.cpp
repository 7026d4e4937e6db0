// compute/contour/contour_dual.cpp - the tile cache of the contourer and the assembly of the global mesh.
#include "compute/contour/contour_dual.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <limits>
#include <string>
#include <sstream>
#include <utility>

#include "compute/parallel/task_pool.hpp"
#include "core/error.hpp"

namespace tridex::compute {

std::uint64_t fresh_tile_version() {
    static std::atomic<std::uint64_t> counter{0};
    return ++counter;
}

namespace {

std::uint64_t next_version() { return fresh_tile_version(); }

bool same_piece(const contour::TileMesh& a, const contour::TileMesh& b) {
    return a.keys == b.keys && a.grid == b.grid && a.materials == b.materials && a.triangles == b.triangles &&
           a.foreign == b.foreign;
}

constexpr std::size_t kAbsent = contour::TileMesh::kNotOwned;

/// True when vertex `key` has the same position and material in both pieces (false when either lacks it).
bool same_vertex(const contour::TileMesh& now, const contour::TileMesh& before, contour::VertexKey key) {
    const std::size_t a = now.find(key), b = before.find(key);
    if (a == kAbsent || b == kAbsent) return false;
    return now.grid[a] == before.grid[b] && now.materials[a] == before.materials[b];
}

}  // namespace

Contourer::Contourer(const TriDexel& model) : lattice_(model.lattice), tiles_(model.tiles.tiles) {
    for (int a = 0; a < 3; ++a) {
        codec_.nodes[a] = lattice_.cells[a] + 1;
        codec_.tiles[a] = tiles_[a];
    }
    tile_meshes_.resize(static_cast<std::size_t>(tiles_[0]) * tiles_[1] * tiles_[2]);
    versions_.assign(tile_meshes_.size(), 0);
    contoured_.assign(tile_meshes_.size(), 0);
    triangle_counts_.assign(tile_meshes_.size(), 0);
    changes_ = TileChangeLog(TileChangeLog::entries_for(tile_meshes_.size()));
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

std::size_t Contourer::update(TriDexel& model, const ProgressFn& progress) {
    check_model(model);
    std::size_t redone = 0, cells = 0, partial_tiles = 0;
    std::vector<std::array<int, 3>> dirty;
    for (int tz = 0; tz < tiles_[2]; ++tz)
        for (int ty = 0; ty < tiles_[1]; ++ty)
            for (int tx = 0; tx < tiles_[0]; ++tx)
                if (model.tiles.dirty[model.tiles.index(tx, ty, tz)]) dirty.push_back({tx, ty, tz});
    // Tiles whose piece changed, with their previous piece (to tell which borrowed vertices moved); in tile order.
    std::vector<std::pair<std::size_t, contour::TileMesh>> changed;
    std::vector<contour::TileMesh> previous(dirty.size());
    for (std::size_t i = 0; i < dirty.size(); ++i)
        previous[i] = std::move(tile_meshes_[model.tiles.index(dirty[i][0], dirty[i][1], dirty[i][2])]);
    // One task per dirty tile on the task pool: each reads the model only and writes its own tile, with the
    // scratch contourer of its pool slot (a tile's result does not depend on which slot runs it).
    const int threads = dirty.size() >= kParallelTiles ? 0 : 1;
    const std::size_t slots = pool_slots(threads);
    if (workers_.size() < slots) workers_.resize(slots);
    // A tile this Contourer has contoured before and whose flag gives its changed cells redoes only those.
    std::vector<const CellBox*> partial(dirty.size(), nullptr);
    for (std::size_t i = 0; i < dirty.size(); ++i) {
        const std::size_t idx = model.tiles.index(dirty[i][0], dirty[i][1], dirty[i][2]);
        if (contoured_[idx]) partial[i] = model.tiles.partial_cells(idx);
    }
    pool_for_progress(
        dirty.size(), 1,
        [&](const Chunk& chunk) {
            contour::TileContourer& c = workers_[chunk.slot];
            for (std::size_t k = chunk.first; k < chunk.last; ++k)
                c.run(model, dirty[k], tile_meshes_[model.tiles.index(dirty[k][0], dirty[k][1], dirty[k][2])],
                      partial[k] != nullptr ? &previous[k] : nullptr, partial[k]);
        },
        progress, threads);
    for (std::size_t i = 0; i < dirty.size(); ++i) {
        const std::size_t idx = model.tiles.index(dirty[i][0], dirty[i][1], dirty[i][2]);
        cells += tile_meshes_[idx].cells_visited;
        contoured_[idx] = 1;
        triangle_counts_[idx] = static_cast<std::uint32_t>(tile_meshes_[idx].triangles.size());
        ++redone;
        if (partial[i] != nullptr) ++partial_tiles;
        if (!same_piece(previous[i], tile_meshes_[idx])) changed.emplace_back(idx, std::move(previous[i]));
    }
    model.clear_dirty();
    bump_versions(changed);
    last_tiles_ = redone;
    last_partial_tiles_ = partial_tiles;
    last_cells_ = cells;
    return redone;
}

void Contourer::bump_versions(const std::vector<std::pair<std::size_t, contour::TileMesh>>& changed) {
    if (changed.empty()) return;
    const std::uint64_t v = next_version();
    // Position in `changed` + 1 of each tile (0 = unchanged).
    std::vector<std::uint32_t> slot(tile_meshes_.size(), 0);
    for (std::size_t i = 0; i < changed.size(); ++i) slot[changed[i].first] = static_cast<std::uint32_t>(i + 1);
    std::vector<std::size_t> bump;
    std::vector<std::uint8_t> checked(tile_meshes_.size(), 0);
    for (const auto& [idx, previous] : changed) {
        bump.push_back(idx);
        // A tile borrows only vertices anchored within one cell of it, so lenders are its 26 neighbours.
        const int tx = static_cast<int>(idx % static_cast<std::size_t>(tiles_[0]));
        const int ty = static_cast<int>(idx / static_cast<std::size_t>(tiles_[0]) % static_cast<std::size_t>(tiles_[1]));
        const int tz = static_cast<int>(idx / (static_cast<std::size_t>(tiles_[0]) * static_cast<std::size_t>(tiles_[1])));
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int x = tx + dx, y = ty + dy, z = tz + dz;
                    if (x < 0 || y < 0 || z < 0 || x >= tiles_[0] || y >= tiles_[1] || z >= tiles_[2]) continue;
                    const std::size_t n = static_cast<std::size_t>(x) +
                                          static_cast<std::size_t>(tiles_[0]) * (static_cast<std::size_t>(y) + static_cast<std::size_t>(tiles_[1]) * static_cast<std::size_t>(z));
                    if (slot[n] != 0 || checked[n]) continue;
                    checked[n] = 1;
                    for (const contour::VertexKey key : tile_meshes_[n].foreign) {
                        const std::size_t owner = codec_.owner_tile(key);
                        if (slot[owner] == 0) continue;
                        if (!same_vertex(tile_meshes_[owner], changed[slot[owner] - 1].second, key)) {
                            bump.push_back(n);
                            break;
                        }
                    }
                }
    }
    normal_sharers(changed, slot, bump);
    for (const std::size_t t : bump) {
        changes_.add(v, t);  // recorded first: a record of a change that did not happen costs only a visit
        versions_[t] = v;
    }
}

void Contourer::check_tile(std::size_t tile) const {
    if (tile >= tile_meshes_.size())
        throw Error("contour: tile " + std::to_string(tile) + " out of range (the lattice has " +
                    std::to_string(tile_meshes_.size()) + " tiles)");
}

std::size_t Contourer::tile_triangle_count(std::size_t tile) const {
    check_tile(tile);
    return triangle_counts_[tile];
}

std::uint64_t Contourer::tile_version(std::size_t tile) const {
    check_tile(tile);
    return versions_[tile];
}

std::pair<std::size_t, std::size_t> Contourer::owned_vertex(contour::VertexKey key) const {
    const std::size_t t = codec_.owner_tile(key);
    const std::size_t i = tile_meshes_[t].find(key);
    if (i == kAbsent)
        throw Error("contour: tile " + std::to_string(t) +
                    " lacks a vertex its neighbour needs; the model changed without mark_dirty() covering the change");
    return {t, i};
}

TriMesh Contourer::tile_mesh(std::size_t tile) const {
    std::vector<std::uint8_t> materials;
    return tile_mesh(tile, materials);
}

TriMesh Contourer::tile_mesh(std::size_t tile, std::vector<std::uint8_t>& materials) const {
    return assemble_tile(tile, materials, nullptr);
}

TriMesh Contourer::tile_mesh(std::size_t tile, std::vector<std::uint8_t>& materials, std::vector<Vec3>& normals) const {
    std::vector<contour::VertexKey> keys;
    TriMesh m = assemble_tile(tile, materials, &keys);
    surface_normals(tile, m, keys, normals);
    return m;
}

TriMesh Contourer::assemble_tile(std::size_t tile, std::vector<std::uint8_t>& materials,
                                 std::vector<contour::VertexKey>* keys) const {
    check_tile(tile);
    materials.clear();
    if (keys) keys->clear();
    const contour::TileMesh& tm = tile_meshes_[tile];
    constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> local(tm.keys.size(), kUnused), foreign(tm.foreign.size(), kUnused);
    TriMesh m;
    m.triangles.reserve(tm.triangles.size());
    m.positions.reserve(tm.keys.size() + tm.foreign.size());
    materials.reserve(tm.keys.size() + tm.foreign.size());
    // Own vertices first (in key order), then borrowed ones (in key order): a stable layout.
    for (const auto& tri : tm.triangles)
        for (const std::uint32_t r : tri)
            if (r < contour::TileMesh::kForeign) local[r] = 0;
    for (std::size_t i = 0; i < local.size(); ++i)
        if (local[i] == 0) {
            local[i] = static_cast<std::uint32_t>(m.positions.size());
            m.positions.push_back(lattice_.to_world(tm.grid[i]));
            materials.push_back(tm.materials[i]);
            if (keys) keys->push_back(tm.keys[i]);
        }
    for (const auto& tri : tm.triangles)
        for (const std::uint32_t r : tri)
            if (r >= contour::TileMesh::kForeign) foreign[r - contour::TileMesh::kForeign] = 0;
    for (std::size_t i = 0; i < foreign.size(); ++i)
        if (foreign[i] == 0) {
            foreign[i] = static_cast<std::uint32_t>(m.positions.size());
            const auto [owner, at] = owned_vertex(tm.foreign[i]);
            m.positions.push_back(lattice_.to_world(tile_meshes_[owner].grid[at]));
            materials.push_back(tile_meshes_[owner].materials[at]);
            if (keys) keys->push_back(tm.foreign[i]);
        }
    for (const auto& tri : tm.triangles) {
        std::array<std::uint32_t, 3> g{};
        for (int v = 0; v < 3; ++v)
            g[v] = tri[v] < contour::TileMesh::kForeign ? local[tri[v]] : foreign[tri[v] - contour::TileMesh::kForeign];
        m.triangles.push_back(g);
    }
    return m;
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

std::vector<std::uint8_t> Contourer::mesh_materials() const {
    std::size_t n = 0;
    for (const contour::TileMesh& tm : tile_meshes_) n += tm.materials.size();
    std::vector<std::uint8_t> out;
    out.reserve(n);
    for (const contour::TileMesh& tm : tile_meshes_) out.insert(out.end(), tm.materials.begin(), tm.materials.end());
    return out;
}

ContourStats Contourer::stats() const {
    ContourStats s;
    s.tiles = tile_meshes_.size();
    s.tiles_recontoured = last_tiles_;
    s.cells_visited = last_cells_;
    s.tiles_partial = last_partial_tiles_;
    for (const contour::TileMesh& tm : tile_meshes_) {
        s.vertices += tm.keys.size();
        s.triangles += tm.triangles.size();
        s.fallbacks += tm.fallbacks;
        s.split_faces += tm.split_faces;
        s.qef_vertices += tm.qef_vertices;
        s.qef_truncated += tm.qef_truncated;
        s.qef_rejected += tm.qef_rejected;
        s.qef_clamped += tm.qef_clamped;
    }
    return s;
}

}  // namespace tridex::compute
