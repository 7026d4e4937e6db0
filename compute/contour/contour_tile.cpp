// compute/contour/contour_tile.cpp - manifold dual contouring of one tile (see contour_tile.hpp for the method).
#include "compute/contour/contour_tile.hpp"

#include "compute/contour/contour_qef.hpp"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstdlib>

namespace tridex::compute::contour {
namespace {

constexpr int kT = TileGrid::kTileCells;

Node plus(Node n, int axis, int d) {
    n[axis] += d;
    return n;
}

/// Material of the crossing nearest to `p` among `n` crossings (points, materials); on an exact tie
/// the larger material id (see TileContourer, "vertex materials").
std::uint8_t nearest_material(const Vec3& p, const Vec3* points, const std::uint8_t* materials, int n) {
    double best_d = 0.0;
    std::uint8_t best = 0;
    for (int i = 0; i < n; ++i) {
        const Vec3 d = points[i] - p;
        const double d2 = glm::dot(d, d);
        if (i == 0 || d2 < best_d || (d2 == best_d && materials[i] > best)) {
            best_d = d2;
            best = materials[i];
        }
    }
    return best;
}

[[noreturn]] void cannot_happen(const char* what) {
    std::fprintf(stderr, "contour_tile: internal error: %s\n", what);
    std::abort();
}

}  // namespace

Node KeyCodec::anchor(VertexKey k) const {
    std::uint64_t l = k / 32u;
    const int i = static_cast<int>(l % static_cast<std::uint64_t>(nodes[0]));
    l /= static_cast<std::uint64_t>(nodes[0]);
    const int j = static_cast<int>(l % static_cast<std::uint64_t>(nodes[1]));
    return Node{i, j, static_cast<int>(l / static_cast<std::uint64_t>(nodes[1]))};
}

std::size_t KeyCodec::owner_tile(VertexKey k) const {
    const Node n = anchor(k);
    const std::size_t tx = static_cast<std::size_t>(std::min(n[0] / kT, tiles[0] - 1));
    const std::size_t ty = static_cast<std::size_t>(std::min(n[1] / kT, tiles[1] - 1));
    const std::size_t tz = static_cast<std::size_t>(std::min(n[2] / kT, tiles[2] - 1));
    return tx + static_cast<std::size_t>(tiles[0]) * (ty + static_cast<std::size_t>(tiles[1]) * tz);
}

void TileContourer::run(const TriDexel& model, const std::array<int, 3>& t, TileMesh& out, const TileMesh* previous,
                        const CellBox* cells) {
    if (previous == &out) cannot_happen("a partial run must not write over its previous result");
    model_ = &model;
    const auto& lattice_cells = model.lattice.cells;
    for (int a = 0; a < 3; ++a) {
        codec_.nodes[a] = lattice_cells[a] + 1;
        codec_.tiles[a] = model.tiles.tiles[a];
    }
    Node c0{}, c1{};
    for (int a = 0; a < 3; ++a) {
        c0[a] = t[a] * kT;
        c1[a] = std::min(c0[a] + kT, lattice_cells[a]);
        cache_lo_[a] = c0[a] - 1;
    }
    // The cells to visit: the whole tile, or the partial run's box within it.
    const bool partial = previous != nullptr && cells != nullptr;
    Node v0 = c0, v1 = c1;
    if (partial)
        for (int a = 0; a < 3; ++a) {
            v0[a] = std::clamp(cells->lo[a], c0[a], c1[a]);
            v1[a] = std::clamp(cells->hi[a] + 1, v0[a], c1[a]);
        }
    occ_.fill(model, cache_lo_);
    // Invalidate the vertex cache by stamp instead of clearing it (it is ~0.5 MB).
    if (cache_.empty()) cache_.resize(static_cast<std::size_t>(kCacheSpan) * kCacheSpan * kCacheSpan);
    if (edges_.empty()) edges_.resize(3 * static_cast<std::size_t>(kEdgeSpan) * kEdgeSpan * kEdgeSpan);
    if (++stamp_ == 0) {
        for (CellVertices& cv : cache_) cv.stamp = 0;
        for (EdgeSample& es : edges_) es.stamp = 0;
        stamp_ = 1;
    }
    out = TileMesh{};
    verts_.clear();
    tri_keys_.clear();
    tri_cells_.clear();
    fallback_cells_.clear();
    split_face_cells_.clear();
    const auto& cases = cell_cases();
    // Bits of a row mask: bit b is the cell with min node cache_lo_[0] + b; visit cells v0[0] .. v1[0] - 1.
    const int nx = v1[0] - v0[0];
    const std::uint32_t range = nx > 0 ? ((std::uint32_t{1} << nx) - 1u) << (v0[0] - cache_lo_[0]) : 0u;
    for (int k = v0[2]; k < v1[2]; ++k) {
        for (int j = v0[1]; j < v1[1]; ++j) {
            const std::uint32_t r0 = occ_.row(j, k), r1 = occ_.row(j + 1, k), r2 = occ_.row(j, k + 1),
                                r3 = occ_.row(j + 1, k + 1);
            const std::uint32_t any = r0 | r1 | r2 | r3, all = r0 & r1 & r2 & r3;
            const std::uint32_t uniform = (~any & ~(any >> 1)) | (all & (all >> 1));
            std::uint32_t todo = ~uniform & range;
            while (todo != 0u) {
                const int b = std::countr_zero(todo);
                todo &= todo - 1u;
                const Node n{cache_lo_[0] + b, j, k};
                cell_ = TileMesh::local_cell(n[0] - c0[0], j - c0[1], k - c0[2]);
                ++out.cells_visited;
                const CellCase& cc = cases[occ_.config(n)];
                const CellVertices& cv = cell_vertices(n);
                for (int comp = 0; comp < cc.components; ++comp)
                    verts_.push_back({codec_.key(n, comp), cv.pos[comp], cv.material[comp], cv.qef[comp]});
                const bool in = occ_.inside(n);
                for (int a = 0; a < 3; ++a)
                    if (occ_.inside(plus(n, a, 1)) != in) emit_edge(n, a);
                for (int f = 0; f < 3; ++f)
                    if (n[f] >= 1 && face_split(plus(n, f, -1), f)) emit_split_face(n, f);
                tri_cells_.resize(tri_keys_.size(), cell_);
            }
        }
    }
    if (!partial) {
        assemble(c0, nullptr, out);
        return;
    }
    keep_outside(*previous, *cells, c0);
    const std::size_t visited = out.cells_visited;
    if (assemble(c0, previous, out)) return;
    // A kept item referred to a vertex that neither the kept cells nor the redone ones emit: `cells` did not
    // hold every changed cell. Redo the tile whole rather than publish a torn piece.
    run(model, t, out);
    out.cells_visited += visited;
}

void TileContourer::keep_outside(const TileMesh& previous, const CellBox& cells, const Node& c0) {
    // The box in tile-local cell offsets; a local cell index is i + 16 * (j + 16 * k).
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = cells.lo[a] - c0[a];
        hi[a] = cells.hi[a] - c0[a];
    }
    const auto in_box = [&](std::uint16_t c) {
        const int i = c % kT, j = (c / kT) % kT, k = c / (kT * kT);
        return i >= lo[0] && i <= hi[0] && j >= lo[1] && j <= hi[1] && k >= lo[2] && k <= hi[2];
    };
    // Vertices: a vertex is anchored at the cell that emits it (contour_tile.hpp, VertexKey).
    const std::size_t fresh_vertices = verts_.size();
    for (std::size_t v = 0; v < previous.keys.size(); ++v) {
        const Node n = codec_.anchor(previous.keys[v]);
        if (!in_box(TileMesh::local_cell(n[0] - c0[0], n[1] - c0[1], n[2] - c0[2])))
            verts_.push_back({previous.keys[v], previous.grid[v], previous.materials[v], previous.qef[v]});
    }
    // This run's vertices come in key order (cells ascending, slots ascending within a cell), as do the kept ones.
    std::inplace_merge(verts_.begin(), verts_.begin() + static_cast<std::ptrdiff_t>(fresh_vertices), verts_.end(),
                       [](const Vertex& x, const Vertex& y) { return x.key < y.key; });
    // Triangles: both lists are in cell order and no cell is in both, so a merge by cell keeps the whole run's
    // order. A kept triangle's own vertices stay references into `previous` (kPreviousVertex), which
    // assemble() maps to the new indices in one pass instead of a search per corner.
    const auto key_of = [&](std::uint32_t r) {
        return r < TileMesh::kForeign ? kPreviousVertex | r : previous.foreign[r - TileMesh::kForeign];
    };
    std::vector<std::array<VertexKey, 3>> keys;
    std::vector<std::uint16_t> tri_cells;
    keys.reserve(previous.triangles.size() + tri_keys_.size());
    tri_cells.reserve(keys.capacity());
    std::size_t fresh = 0;
    for (std::size_t tr = 0; tr < previous.triangles.size(); ++tr) {
        const std::uint16_t c = previous.triangle_cells[tr];
        if (in_box(c)) continue;
        for (; fresh < tri_keys_.size() && tri_cells_[fresh] < c; ++fresh) {
            keys.push_back(tri_keys_[fresh]);
            tri_cells.push_back(tri_cells_[fresh]);
        }
        const auto& ref = previous.triangles[tr];
        keys.push_back({key_of(ref[0]), key_of(ref[1]), key_of(ref[2])});
        tri_cells.push_back(c);
    }
    keys.insert(keys.end(), tri_keys_.begin() + static_cast<std::ptrdiff_t>(fresh), tri_keys_.end());
    tri_cells.insert(tri_cells.end(), tri_cells_.begin() + static_cast<std::ptrdiff_t>(fresh), tri_cells_.end());
    tri_keys_.swap(keys);
    tri_cells_.swap(tri_cells);
    const auto keep_cells = [&](const std::vector<std::uint16_t>& kept, std::vector<std::uint16_t>& into) {
        for (const std::uint16_t c : kept)
            if (!in_box(c)) into.push_back(c);
        std::sort(into.begin(), into.end());
    };
    keep_cells(previous.fallback_cells, fallback_cells_);
    keep_cells(previous.split_face_cells, split_face_cells_);
}

bool TileContourer::assemble(const Node& c0, const TileMesh* previous, TileMesh& out) {
    const auto by_key = [](const Vertex& x, const Vertex& y) { return x.key < y.key; };
    if (!std::is_sorted(verts_.begin(), verts_.end(), by_key)) std::sort(verts_.begin(), verts_.end(), by_key);
    out.keys.reserve(verts_.size());
    out.grid.reserve(verts_.size());
    out.materials.reserve(verts_.size());
    out.qef.reserve(verts_.size());
    for (const Vertex& v : verts_) {
        out.keys.push_back(v.key);
        out.grid.push_back(v.pos);
        out.materials.push_back(v.material);
        out.qef.push_back(v.qef);
        if (v.qef & kQefRejected) {
            ++out.qef_rejected;
        } else {
            if (v.qef & kQefNormals) ++out.qef_vertices;
            if (v.qef & kQefTruncated) ++out.qef_truncated;
            if (v.qef & kQefClamped) ++out.qef_clamped;
        }
    }
    out.fallback_cells = fallback_cells_;
    out.split_face_cells = split_face_cells_;
    out.fallbacks = fallback_cells_.size();
    out.split_faces = split_face_cells_.size();
    out.triangle_cells = tri_cells_;
    // Resolve keys: local vertices to their index, others (first numbered in order of use) to the sorted
    // list of foreign keys.
    out.triangles.reserve(tri_keys_.size());
    std::vector<VertexKey>& pending = out.foreign;
    // The new index of each vertex of `previous` (a partial run's kept triangles refer to them): both
    // key lists are sorted.
    remap_.clear();
    if (previous != nullptr) {
        remap_.resize(previous->keys.size(), TileMesh::kForeign);
        std::size_t at = 0;
        for (std::size_t r = 0; r < previous->keys.size(); ++r) {
            while (at < out.keys.size() && out.keys[at] < previous->keys[r]) ++at;
            if (at < out.keys.size() && out.keys[at] == previous->keys[r]) remap_[r] = static_cast<std::uint32_t>(at);
        }
    }
    for (const auto& tri : tri_keys_) {
        std::array<std::uint32_t, 3> ref{};
        for (int v = 0; v < 3; ++v) {
            if (tri[v] & kPreviousVertex) {
                ref[v] = remap_[static_cast<std::size_t>(tri[v] & ~kPreviousVertex)];
                if (ref[v] == TileMesh::kForeign)
                    return false;  // the box missed a change: the caller redoes the tile whole
                continue;
            }
            const auto it = std::lower_bound(out.keys.begin(), out.keys.end(), tri[v]);
            if (it != out.keys.end() && *it == tri[v]) {
                ref[v] = static_cast<std::uint32_t>(it - out.keys.begin());
            } else {
                ref[v] = TileMesh::kForeign + static_cast<std::uint32_t>(pending.size());
                pending.push_back(tri[v]);
            }
        }
        out.triangles.push_back(ref);
    }
    std::vector<VertexKey> used = pending;
    std::sort(out.foreign.begin(), out.foreign.end());
    out.foreign.erase(std::unique(out.foreign.begin(), out.foreign.end()), out.foreign.end());
    const std::size_t self = codec_.owner_tile(codec_.key(c0, 0));
    for (const VertexKey k : out.foreign) {
        if (codec_.owner_tile(k) != self) continue;
        if (previous != nullptr) return false;  // the box missed a change: the caller redoes the tile whole
        cannot_happen("a vertex of this tile was not emitted");
    }
    for (auto& ref : out.triangles)
        for (std::uint32_t& r : ref)
            if (r >= TileMesh::kForeign)
                r = TileMesh::kForeign + static_cast<std::uint32_t>(std::lower_bound(out.foreign.begin(), out.foreign.end(), used[r - TileMesh::kForeign]) - out.foreign.begin());
    return true;
}

bool TileContourer::face_split(const Node& lower, int f) const {
    const auto& cases = cell_cases();
    const int below = cases[occ_.config(lower)].merged_faces >> (2 * f + 1);
    const int above = cases[occ_.config(plus(lower, f, 1))].merged_faces >> (2 * f);
    return ((below & above) & 1) != 0;
}

void TileContourer::emit_edge(const Node& n, int a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const bool start_in = occ_.inside(n);
    const EdgeCrossing x = edge_sample(n, a, start_in).crossing;
    if (x.fallback) fallback_cells_.push_back(cell_);
    // The 4 cells around the edge, counter-clockwise seen from +a (offsets along b, c).
    static constexpr int kDb[4] = {-1, 0, 0, -1}, kDc[4] = {-1, -1, 0, 0};
    std::array<Node, 4> ring{};
    std::array<int, 4> comp{};
    std::array<VertexKey, 4> rk{};
    for (int r = 0; r < 4; ++r) {
        ring[r] = plus(plus(n, b, kDb[r]), c, kDc[r]);
        const int local = 4 * a + (-kDb[r]) + 2 * (-kDc[r]);
        comp[r] = cell_cases()[occ_.config(ring[r])].edge_component[local];
        if (comp[r] < 0) cannot_happen("sign-change edge without a component");
        rk[r] = codec_.key(ring[r], comp[r]);
    }
    // Face between ring[r] and ring[r+1]: its axis and its lower cell.
    const int face_axis[4] = {b, c, b, c};
    const Node face_lower[4] = {ring[0], ring[1], ring[3], ring[0]};
    const Node inside_end = start_in ? n : plus(n, a, 1);
    VertexKey poly[8];
    int count = 0;
    bool any_split = false;
    for (int r = 0; r < 4; ++r) {
        poly[count++] = rk[r];
        const int g = face_axis[r];
        if (!face_split(face_lower[r], g)) continue;
        const Node fmin = plus(face_lower[r], g, 1);
        const int corner = (inside_end[(g + 1) % 3] - fmin[(g + 1) % 3]) + 2 * (inside_end[(g + 2) % 3] - fmin[(g + 2) % 3]);
        poly[count++] = codec_.key(fmin, 8 + 4 * g + corner);
        any_split = true;
    }
    if (!any_split) {
        // Ring order (0,1,2,3) has normal +a; (0,3,2,1) has normal -a. Split along the shorter diagonal.
        const std::array<int, 4> o = start_in ? std::array<int, 4>{0, 1, 2, 3} : std::array<int, 4>{0, 3, 2, 1};
        Vec3 p[4];
        for (int r = 0; r < 4; ++r) p[r] = vertex(ring[o[r]], comp[o[r]]);
        if (glm::length(p[0] - p[2]) <= glm::length(p[1] - p[3])) {
            tri_keys_.push_back({rk[o[0]], rk[o[1]], rk[o[2]]});
            tri_keys_.push_back({rk[o[0]], rk[o[2]], rk[o[3]]});
        } else {
            tri_keys_.push_back({rk[o[1]], rk[o[2]], rk[o[3]]});
            tri_keys_.push_back({rk[o[1]], rk[o[3]], rk[o[0]]});
        }
        return;
    }
    if (!start_in) std::reverse(poly, poly + count);  // outward normal is -a
    const VertexKey centre = codec_.key(n, 4 + a);
    verts_.push_back({centre, crossing_point(n, a, x), x.material, 0});
    for (int i = 0; i < count; ++i) tri_keys_.push_back({centre, poly[i], poly[(i + 1) % count]});
}

void TileContourer::emit_split_face(const Node& n, int f) {
    const int f1 = (f + 1) % 3, f2 = (f + 2) % 3;
    for (int idx = 0; idx < 4; ++idx) {
        const Node p = plus(plus(n, f1, idx & 1), f2, (idx >> 1) & 1);
        if (!occ_.inside(p)) continue;
        // The segment around inside corner p joins the crossings of the two face edges at p. Its vertex: the
        // QEF of those crossings whose normal is known, with the normals' components across the face dropped
        // (the face's trace of each tangent plane), minimised in the rectangle spanned by p and the two
        // crossings (which stays on p's side of the face); the crossings' mean without normals. When the two
        // crossings lie on the facing walls of a sheet thinner than the cell (nearly opposite normals), only the
        // first crossing's normal counts, so the vertex lies on that wall instead of inside the sheet.
        Vec3 sum(0.0);
        std::array<Vec3, 2> pts{}, qp{}, qn{};
        std::array<std::uint8_t, 2> mats{};
        Vec3 first(0.0);  // the first kept normal, before its component across the face is dropped
        int m = 0, q = 0;
        for (const int g : {f1, f2}) {
            const int off = g == f1 ? (idx & 1) : ((idx >> 1) & 1);
            const Node s = plus(p, g, -off);  // edge start node
            const EdgeSample& es = edge_sample(s, g, occ_.inside(s));
            pts[m] = crossing_point(s, g, es.crossing);
            mats[m] = es.crossing.material;
            sum += pts[m++];
            // A crease side's face may not be this segment's; the second of two nearly opposite normals is a
            // sheet's other wall (as in cell_vertices), whose trace would cross the first's far outside.
            if (es.has_normal && !es.crease && !(q == 1 && normal_dot(first, es.normal) < kOpposedNormalCos)) {
                if (q == 0) first = es.normal;
                qp[q] = pts[m - 1];
                qn[q] = es.normal;
                qn[q++][f] = 0.0;
            }
        }
        Vec3 pos = 0.5 * sum;
        if (q > 0) {
            const Vec3 corner(p[0], p[1], p[2]);
            const Vec3 lo = glm::min(corner, glm::min(pts[0], pts[1])), hi = glm::max(corner, glm::max(pts[0], pts[1]));
            pos = glm::clamp(qef_vertex(pos, qp.data(), qn.data(), q, Vec3(n[0], n[1], n[2])), lo, hi);
        }
        verts_.push_back({codec_.key(n, 8 + 4 * f + idx), pos, nearest_material(pos, pts.data(), mats.data(), 2), 0});
    }
    split_face_cells_.push_back(cell_);
}

}  // namespace tridex::compute::contour
