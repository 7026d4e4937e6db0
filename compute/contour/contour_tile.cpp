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

std::size_t KeyCodec::owner_tile(VertexKey k) const {
    std::uint64_t l = k / 32u;
    const int i = static_cast<int>(l % static_cast<std::uint64_t>(nodes[0]));
    l /= static_cast<std::uint64_t>(nodes[0]);
    const int j = static_cast<int>(l % static_cast<std::uint64_t>(nodes[1]));
    const int kk = static_cast<int>(l / static_cast<std::uint64_t>(nodes[1]));
    const std::size_t tx = static_cast<std::size_t>(std::min(i / kT, tiles[0] - 1));
    const std::size_t ty = static_cast<std::size_t>(std::min(j / kT, tiles[1] - 1));
    const std::size_t tz = static_cast<std::size_t>(std::min(kk / kT, tiles[2] - 1));
    return tx + static_cast<std::size_t>(tiles[0]) * (ty + static_cast<std::size_t>(tiles[1]) * tz);
}

void TileContourer::run(const TriDexel& model, const std::array<int, 3>& t, TileMesh& out) {
    model_ = &model;
    const auto& cells = model.lattice.cells;
    for (int a = 0; a < 3; ++a) {
        codec_.nodes[a] = cells[a] + 1;
        codec_.tiles[a] = model.tiles.tiles[a];
    }
    Node c0{}, c1{};
    for (int a = 0; a < 3; ++a) {
        c0[a] = t[a] * kT;
        c1[a] = std::min(c0[a] + kT, cells[a]);
        cache_lo_[a] = c0[a] - 1;
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
    const auto& cases = cell_cases();
    const int nx = c1[0] - c0[0];
    // Bits 1..nx of a row mask are the cells c0[0] .. c1[0] - 1 (bit b: cell with min node lo + b).
    const std::uint32_t range = nx > 0 ? ((std::uint32_t{1} << nx) - 1u) << 1 : 0u;
    for (int k = c0[2]; k < c1[2]; ++k) {
        for (int j = c0[1]; j < c1[1]; ++j) {
            const std::uint32_t r0 = occ_.row(j, k), r1 = occ_.row(j + 1, k), r2 = occ_.row(j, k + 1),
                                r3 = occ_.row(j + 1, k + 1);
            const std::uint32_t any = r0 | r1 | r2 | r3, all = r0 & r1 & r2 & r3;
            const std::uint32_t uniform = (~any & ~(any >> 1)) | (all & (all >> 1));
            std::uint32_t todo = ~uniform & range;
            while (todo != 0u) {
                const int b = std::countr_zero(todo);
                todo &= todo - 1u;
                const Node n{cache_lo_[0] + b, j, k};
                ++out.cells_visited;
                const CellCase& cc = cases[occ_.config(n)];
                const CellVertices& cv = cell_vertices(n);
                for (int comp = 0; comp < cc.components; ++comp) {
                    verts_.push_back({codec_.key(n, comp), cv.pos[comp], cv.material[comp]});
                    const std::uint8_t how = cv.qef[comp];
                    if (how & kQefRejected) {
                        ++out.qef_rejected;
                    } else {
                        if (how & kQefNormals) ++out.qef_vertices;
                        if (how & kQefTruncated) ++out.qef_truncated;
                        if (how & kQefClamped) ++out.qef_clamped;
                    }
                }
                const bool in = occ_.inside(n);
                for (int a = 0; a < 3; ++a)
                    if (occ_.inside(plus(n, a, 1)) != in) emit_edge(n, a, out);
                for (int f = 0; f < 3; ++f)
                    if (n[f] >= 1 && face_split(plus(n, f, -1), f)) emit_split_face(n, f, out);
            }
        }
    }
    std::sort(verts_.begin(), verts_.end(), [](const Vertex& x, const Vertex& y) { return x.key < y.key; });
    out.keys.reserve(verts_.size());
    out.grid.reserve(verts_.size());
    out.materials.reserve(verts_.size());
    for (const Vertex& v : verts_) {
        out.keys.push_back(v.key);
        out.grid.push_back(v.pos);
        out.materials.push_back(v.material);
    }
    // Resolve keys: local vertices to their index, others (first numbered in order of use) to the sorted
    // list of foreign keys.
    out.triangles.reserve(tri_keys_.size());
    std::vector<VertexKey>& pending = out.foreign;
    for (const auto& tri : tri_keys_) {
        std::array<std::uint32_t, 3> ref{};
        for (int v = 0; v < 3; ++v) {
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
    for (const VertexKey k : out.foreign)
        if (codec_.owner_tile(k) == self) cannot_happen("a vertex of this tile was not emitted");
    for (auto& ref : out.triangles)
        for (std::uint32_t& r : ref)
            if (r >= TileMesh::kForeign)
                r = TileMesh::kForeign + static_cast<std::uint32_t>(std::lower_bound(out.foreign.begin(), out.foreign.end(), used[r - TileMesh::kForeign]) - out.foreign.begin());
}

bool TileContourer::face_split(const Node& lower, int f) const {
    const auto& cases = cell_cases();
    const int below = cases[occ_.config(lower)].merged_faces >> (2 * f + 1);
    const int above = cases[occ_.config(plus(lower, f, 1))].merged_faces >> (2 * f);
    return ((below & above) & 1) != 0;
}

void TileContourer::emit_edge(const Node& n, int a, TileMesh& out) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const bool start_in = occ_.inside(n);
    const EdgeCrossing x = edge_sample(n, a, start_in).crossing;
    if (x.fallback) ++out.fallbacks;
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
    verts_.push_back({centre, crossing_point(n, a, x), x.material});
    for (int i = 0; i < count; ++i) tri_keys_.push_back({centre, poly[i], poly[(i + 1) % count]});
}

void TileContourer::emit_split_face(const Node& n, int f, TileMesh& out) {
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
        verts_.push_back({codec_.key(n, 8 + 4 * f + idx), pos, nearest_material(pos, pts.data(), mats.data(), 2)});
    }
    ++out.split_faces;
}

}  // namespace tridex::compute::contour
