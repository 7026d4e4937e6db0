// compute/contour/contour_tile_normals.cpp - the whole surface's vertex normals of one tile's mesh, and which
// neighbour tiles' normals an update changed.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/tile_group_box.hpp"

namespace tridex::compute {

namespace {

constexpr int kT = TileGrid::kTileCells;
// Cells beyond a tile's box [t0, t0 + kT) whose triangles may use a vertex of its mesh: a triangle emitted by cell c
// uses vertices anchored at c - 1 .. c, so the tile's own triangles use vertices anchored at t0 - 1 .. t0 + kT - 1,
// and other triangles using those are emitted by cells t0 - 1 .. t0 + kT.
constexpr int kReachBelow = 1, kReachAbove = 1;
constexpr std::size_t kAbsent = contour::TileMesh::kNotOwned;

contour::VertexKey key_of(const contour::TileMesh& piece, std::uint32_t r) {
    return r < contour::TileMesh::kForeign ? piece.keys[r] : piece.foreign[r - contour::TileMesh::kForeign];
}

// Calls f(u, self) for each tile u of the 3 x 3 x 3 block around tile t that lies in the grid, in ascending index
// order (self: u is t).
template <typename F>
void for_each_around(const std::array<int, 3>& t, const std::array<int, 3>& tiles, F&& f) {
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const std::array<int, 3> u{t[0] + dx, t[1] + dy, t[2] + dz};
                if (u[0] >= 0 && u[1] >= 0 && u[2] >= 0 && u[0] < tiles[0] && u[1] < tiles[1] && u[2] < tiles[2])
                    f(u, (dx | dy | dz) == 0);
            }
}

// Whether tile `piece` holds vertex `key` (owns it or borrows it).
bool holds(const contour::TileMesh& piece, contour::VertexKey key) {
    return piece.find(key) != kAbsent || std::binary_search(piece.foreign.begin(), piece.foreign.end(), key);
}

// Appends to `out` the keys of the vertices `now` owns that `before` owned too at another position.
void own_moved(const contour::TileMesh& before, const contour::TileMesh& now, std::vector<contour::VertexKey>& out) {
    for (std::size_t i = 0, j = 0; i < now.keys.size() && j < before.keys.size();) {  // both ascending
        if (now.keys[i] < before.keys[j]) {
            ++i;
        } else if (before.keys[j] < now.keys[i]) {
            ++j;
        } else {
            if (before.grid[j] != now.grid[i]) out.push_back(now.keys[i]);
            ++i;
            ++j;
        }
    }
}

// Whether a tile around tile t (t itself aside) is outside the update (`slot` 0), not bumped yet and has triangles.
bool outside_neighbour(const std::array<int, 3>& t, const std::array<int, 3>& tiles,
                       const std::vector<std::uint32_t>& slot, const std::vector<std::uint8_t>& marked,
                       const std::vector<std::uint32_t>& triangles) {
    bool any = false;
    for_each_around(t, tiles, [&](const std::array<int, 3>& u, bool self) {
        const std::size_t n = grid_index(u, tiles);
        any = any || (!self && slot[n] == 0 && !marked[n] && triangles[n] > 0);
    });
    return any;
}

// Appends to `out` the vertices of triangles [from, to) of `piece` (the tile at `t`) anchored within one cell of the
// tile's border: no other tile uses the others.
void border_keys(const contour::KeyCodec& codec, const std::array<int, 3>& t, const contour::TileMesh& piece,
                 std::size_t from, std::size_t to, std::vector<contour::VertexKey>& out) {
    for (std::size_t k = from; k < to; ++k)
        for (const std::uint32_t r : piece.triangles[k]) {
            const contour::VertexKey key = key_of(piece, r);
            const contour::Node a = codec.anchor(key);
            bool border = false;
            for (int ax = 0; ax < 3; ++ax) {
                const int x = a[ax] - t[ax] * kT;
                border = border || x <= 0 || x >= kT - 1;
            }
            if (border) out.push_back(key);
        }
}

// Appends to `out` the border vertices (border_keys) of every triangle the update of the tile at `t` from `before` to
// `now` added, removed or reshaped (`moved`, sorted: its vertices that moved), cell by cell: triangles are listed by
// ascending emitting cell, and a cell that emitted the same triangles keeps their order. A cell whose local
// coordinates are all 2 .. kT - 2 is skipped: its triangles use vertices anchored at 1 .. kT - 2, no other tile's.
void reshaped_border_keys(const contour::KeyCodec& codec, const std::array<int, 3>& t, const contour::TileMesh& before,
                          const contour::TileMesh& now, const std::vector<contour::VertexKey>& moved,
                          std::vector<contour::VertexKey>& out) {
    if (before.triangle_cells.size() != before.triangles.size() || now.triangle_cells.size() != now.triangles.size()) {
        border_keys(codec, t, before, 0, before.triangles.size(), out);
        border_keys(codec, t, now, 0, now.triangles.size(), out);
        return;
    }
    std::size_t i = 0, j = 0;
    while (i < before.triangles.size() || j < now.triangles.size()) {
        const int ci = i < before.triangles.size() ? before.triangle_cells[i] : 1 << 30;
        const int cj = j < now.triangles.size() ? now.triangle_cells[j] : 1 << 30;
        const int cell = std::min(ci, cj);
        std::size_t i2 = i, j2 = j;
        while (i2 < before.triangles.size() && before.triangle_cells[i2] == cell) ++i2;
        while (j2 < now.triangles.size() && now.triangle_cells[j2] == cell) ++j2;
        bool inner = true;
        for (const int x : {cell % kT, cell / kT % kT, cell / (kT * kT)}) inner = inner && x >= 2 && x <= kT - 2;
        bool same = inner || i2 - i == j2 - j;
        for (std::size_t k = 0; !inner && same && k < i2 - i; ++k)
            for (int v = 0; v < 3 && same; ++v) {
                const contour::VertexKey key = key_of(now, now.triangles[j + k][v]);
                same = key == key_of(before, before.triangles[i + k][v]) &&
                       !std::binary_search(moved.begin(), moved.end(), key);
            }
        if (!same) {
            border_keys(codec, t, before, i, i2, out);
            border_keys(codec, t, now, j, j2, out);
        }
        i = i2;
        j = j2;
    }
}

}  // namespace

void Contourer::surface_normals(std::size_t tile, const TriMesh& mesh, const std::vector<contour::VertexKey>& keys,
                                std::vector<Vec3>& normals) const {
    // The mesh's vertices by key: an open-addressed table at most half full (a neighbour's triangle is looked up
    // three times, and most of those it reads use none of them).
    constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
    std::size_t size = 16;
    while (size < 2 * keys.size()) size *= 2;
    std::vector<std::pair<contour::VertexKey, std::uint32_t>> table(size, {0, kNone});
    const auto slot_of = [&](contour::VertexKey k) {
        return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ull) >> 20) & (size - 1);
    };
    for (std::size_t i = 0; i < keys.size(); ++i) {
        std::size_t h = slot_of(keys[i]);
        while (table[h].second != kNone) h = (h + 1) & (size - 1);
        table[h] = {keys[i], static_cast<std::uint32_t>(i)};
    }
    const auto find = [&](contour::VertexKey k) -> std::uint32_t {
        for (std::size_t h = slot_of(k);; h = (h + 1) & (size - 1))
            if (table[h].second == kNone || table[h].first == k) return table[h].second;
    };
    normals.assign(keys.size(), Vec3(0.0));
    const std::array<int, 3> t = grid_coords(tile, tiles_);
    std::array<int, 3> lo{}, hi{};  // cells (inclusive) whose triangles may use the mesh's vertices
    for (int a = 0; a < 3; ++a) {
        lo[a] = t[a] * kT - kReachBelow;
        hi[a] = (t[a] + 1) * kT - 1 + kReachAbove;
    }
    const auto position = [&](const contour::TileMesh& piece, std::uint32_t r) {
        if (r < contour::TileMesh::kForeign) return lattice_.to_world(piece.grid[r]);
        const auto [owner, i] = owned_vertex(piece.foreign[r - contour::TileMesh::kForeign]);
        return lattice_.to_world(tile_meshes_[owner].grid[i]);
    };
    const auto add = [&](const contour::TileMesh& piece, std::size_t k) {  // triangle k of a neighbour's piece
        const auto& tri = piece.triangles[k];
        std::array<std::uint32_t, 3> mine{};
        bool any = false;
        for (int v = 0; v < 3; ++v) {
            mine[v] = find(key_of(piece, tri[v]));
            any = any || mine[v] != kNone;
        }
        if (!any) return;
        const Vec3 a = position(piece, tri[0]);
        const Vec3 fn = glm::cross(position(piece, tri[1]) - a, position(piece, tri[2]) - a);
        for (int v = 0; v < 3; ++v)
            if (mine[v] != kNone) normals[mine[v]] += fn;
    };
    // Ascending tile order and each tile's triangles in order, as mesh() lists them: the sums are vertex_normals'
    // over mesh(), and any tile sharing a vertex adds the same triangles in the same order.
    for_each_around(t, tiles_, [&](const std::array<int, 3>& u, bool self) {
        if (self) {  // the tile's own triangles: all of them, as assembled in `mesh`
            for (const auto& tri : mesh.triangles) {
                const Vec3& a = mesh.positions[tri[0]];
                const Vec3 fn = glm::cross(mesh.positions[tri[1]] - a, mesh.positions[tri[2]] - a);
                for (const std::uint32_t v : tri) normals[v] += fn;
            }
            return;
        }
        const contour::TileMesh& piece = tile_meshes_[grid_index(u, tiles_)];
        const auto& cells = piece.triangle_cells;
        if (cells.size() != piece.triangles.size()) {  // no cell per triangle: every triangle
            for (std::size_t k = 0; k < piece.triangles.size(); ++k) add(piece, k);
            return;
        }
        // Its cells within [lo, hi], tile-local, visited in ascending order.
        std::array<int, 3> r0{}, r1{};
        bool empty = false;
        for (int a = 0; a < 3; ++a) {
            r0[a] = std::max(lo[a] - u[a] * kT, 0);
            r1[a] = std::min(hi[a] - u[a] * kT, kT - 1);
            empty = empty || r0[a] > r1[a];
        }
        if (empty) return;
        // The cells of slabs z = r0..r1 are one run (cells ascend as x + kT (y + kT z)); x and y are filtered.
        const auto first = std::lower_bound(cells.begin(), cells.end(), kT * kT * r0[2]);
        for (auto it = first; it != cells.end() && *it < kT * kT * (r1[2] + 1); ++it) {
            const int x = *it % kT, y = *it / kT % kT;
            if (x >= r0[0] && x <= r1[0] && y >= r0[1] && y <= r1[1])
                add(piece, static_cast<std::size_t>(it - cells.begin()));
        }
    });
    for (Vec3& n : normals) {
        const double len = glm::length(n);
        n = len > 0.0 ? n / len : Vec3(0.0);
    }
}

void Contourer::normal_sharers(const std::vector<std::pair<std::size_t, contour::TileMesh>>& changed,
                               const std::vector<std::uint32_t>& slot, std::vector<std::size_t>& bump) const {
    std::vector<std::uint8_t> marked(tile_meshes_.size(), 0);
    for (const std::size_t t : bump) marked[t] = 1;
    // Bumps the tiles other than `self`, outside `changed`, that use one of `keys` (sorted): those around each key's
    // anchor, whose cells may emit a triangle using it.
    const auto bump_users = [&](std::vector<contour::VertexKey>& keys, std::size_t self) {
        std::sort(keys.begin(), keys.end());
        keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
        for (const contour::VertexKey k : keys) {
            const contour::Node a = codec_.anchor(k);
            std::array<int, 3> t0{}, t1{};
            for (int ax = 0; ax < 3; ++ax) {
                t0[ax] = std::clamp((a[ax] - 1) / kT, 0, tiles_[ax] - 1);
                t1[ax] = std::clamp((a[ax] + 1) / kT, 0, tiles_[ax] - 1);
            }
            for (int z = t0[2]; z <= t1[2]; ++z)
                for (int y = t0[1]; y <= t1[1]; ++y)
                    for (int x = t0[0]; x <= t1[0]; ++x) {
                        const std::size_t n = grid_index({x, y, z}, tiles_);
                        if (n == self || slot[n] != 0 || marked[n] || triangle_counts_[n] == 0) continue;
                        if (!holds(tile_meshes_[n], k)) continue;
                        marked[n] = 1;
                        bump.push_back(n);
                    }
        }
    };
    std::vector<contour::VertexKey> moved, touched, all_moved;
    for (const auto& [c, before] : changed) {
        const contour::TileMesh& now = tile_meshes_[c];
        moved.clear();
        own_moved(before, now, moved);
        all_moved.insert(all_moved.end(), moved.begin(), moved.end());
        if (!outside_neighbour(grid_coords(c, tiles_), tiles_, slot, marked, triangle_counts_)) continue;
        // Borrowed vertices whose owner changed too and that moved.
        for (const contour::TileMesh* p : {&before, &now})
            for (const contour::VertexKey k : p->foreign) {
                const std::size_t owner = codec_.owner_tile(k);
                if (slot[owner] == 0) continue;
                const contour::TileMesh& old = changed[slot[owner] - 1].second;
                const std::size_t a = tile_meshes_[owner].find(k), b = old.find(k);
                if (a == kAbsent || b == kAbsent || tile_meshes_[owner].grid[a] != old.grid[b]) moved.push_back(k);
            }
        std::sort(moved.begin(), moved.end());
        touched.clear();
        reshaped_border_keys(codec_, grid_coords(c, tiles_), before, now, moved, touched);
        bump_users(touched, c);
    }
    // A triangle of a tile outside `changed` is reshaped too when a changed tile's vertex it uses moved: the normals of
    // its other vertices change, and the tiles using those need new versions (the tile itself borrows the moved
    // vertex: bump_versions has given it one).
    if (all_moved.empty()) return;
    std::sort(all_moved.begin(), all_moved.end());
    std::vector<std::uint8_t> seen(tile_meshes_.size(), 0);
    for (const auto& entry : changed)
        for_each_around(grid_coords(entry.first, tiles_), tiles_, [&](const std::array<int, 3>& u, bool) {
            const std::size_t n = grid_index(u, tiles_);
            if (slot[n] != 0 || seen[n] || triangle_counts_[n] == 0) return;
            seen[n] = 1;
            const contour::TileMesh& piece = tile_meshes_[n];
            if (std::none_of(piece.foreign.begin(), piece.foreign.end(), [&](contour::VertexKey k) {
                    return std::binary_search(all_moved.begin(), all_moved.end(), k);
                }))
                return;  // it borrows no moved vertex
            touched.clear();
            for (std::size_t k = 0; k < piece.triangles.size(); ++k) {
                bool uses = false;
                for (const std::uint32_t r : piece.triangles[k])
                    uses = uses || (r >= contour::TileMesh::kForeign &&
                                    std::binary_search(all_moved.begin(), all_moved.end(), key_of(piece, r)));
                if (uses) border_keys(codec_, grid_coords(n, tiles_), piece, k, k + 1, touched);
            }
            if (!touched.empty()) bump_users(touched, n);
        });
}

}  // namespace tridex::compute
