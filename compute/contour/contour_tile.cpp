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

/// True when a crease normal `crease` (the flat side's, contour::crossing_normal) may stand beside the ordinary
/// normal `plain` in one cell component: they make an acute angle (dot product > 0, summed in a fixed order
/// that the GPU contourer repeats).
/// Dot product of two normals, summed in a fixed order (the GPU contourer repeats it).
double normal_dot(const Vec3& a, const Vec3& b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }

bool crease_normal_fits(const Vec3& crease, const Vec3& plain) { return normal_dot(crease, plain) > 0.0; }

/// Calls fn(q, n) for every crossing with an ordinary normal (not a crease side's) on the edges of the 6 cells
/// face-adjacent to `cell` that do not lie on the shared faces (face f = 0..2, side -1 then +1, cell edges 4a + k
/// ascending): q its point, n its normal (lattice units). Reads the rays directly (those cells lie up to a cell beyond
/// a tile's caches); the GPU contourer visits them in the same order. O(48 edges x crossing_normal).
template <typename Fn>
void for_each_neighbour_plane(const TriDexel& model, const Node& cell, Fn&& fn) {
    for (int f = 0; f < 3; ++f)
        for (int side = -1; side <= 1; side += 2) {
            Node nb = cell;
            nb[f] += side;
            const int shared = side > 0 ? cell[f] + 1 : cell[f];
            for (int e = 0; e < 12; ++e) {
                const int a = e / 4, k = e & 3;
                Node p = nb;
                p[(a + 1) % 3] += k & 1;
                p[(a + 2) % 3] += (k >> 1) & 1;
                if (a != f && p[f] == shared) continue;
                bool in_lattice = true;
                for (int j = 0; j < 3; ++j)
                    if (p[j] < 0 || p[j] + (j == a ? 1 : 0) > model.lattice.cells[j]) in_lattice = false;
                if (!in_lattice) continue;
                const bool in = node_inside(model, p);
                if (in == node_inside(model, plus(p, a, 1))) continue;
                const EdgeCrossing x = edge_crossing(model, a, p, in);
                if (x.fallback || x.exit != in) continue;
                Vec3 nn(0.0);
                bool crease = false;
                if (!crossing_normal(model, a, p, in, x.t, nn, &crease) || crease) continue;
                fn(crossing_point(p, a, x), nn);
            }
        }
}

/// The corner-fill plane of a cell component (see kCornerFillReach): among the neighbour planes
/// (for_each_neighbour_plane) whose normal has a dot product above kCornerFillCos with each of the `count` normals
/// `own` and whose tangent plane has the crossings' mass point `mass` in front of it or at most kCornerFillFront
/// behind, the one whose tangent plane `pos` lies deepest behind (first on ties). Returns true with its point and
/// normal when that depth exceeds kCornerFillDepth. Arithmetic in the order the GPU contourer repeats.
bool corner_fill_plane(const TriDexel& model, const Node& cell, const Vec3& pos, const Vec3& mass, const Vec3* own, int count, Vec3& point,
                       Vec3& normal) {
    bool found = false;
    double deepest = 0.0;
    for_each_neighbour_plane(model, cell, [&](const Vec3& q, const Vec3& nn) {
        for (int i = 0; i < count; ++i)
            if (!(normal_dot(nn, own[i]) > kCornerFillCos)) return;
        if (!(normal_dot(nn, mass - q) >= -kCornerFillFront)) return;
        const double depth = -normal_dot(nn, pos - q);
        if (!found || depth > deepest) {
            found = true;
            deepest = depth;
            point = q;
            normal = nn;
        }
    });
    return found && deepest > kCornerFillDepth;
}

/// Borrowed normals for the `count` crossings of a cell component (see kBorrowReach, kBorrowWrongCos): the neighbour
/// planes (for_each_neighbour_plane) are matched to each own crossing `points[i]` (on an edge along `axes[i]`, leaving
/// material going +axis when `exits[i]`): among those whose normal points out of the material along that edge
/// (component along the axis > 0 for an exit, < 0 for an enter), the one whose tangent plane passes nearest to the
/// point (first on ties), taken when within kBorrowReach. Sets `got[i]` and `normals[i]` for the matched crossings;
/// returns their number. Arithmetic in the order the GPU contourer repeats.
int borrowed_normals(const TriDexel& model, const Node& cell, const Vec3* points, const int* axes, const bool* exits, int count,
                     Vec3* normals, bool* got) {
    std::array<double, 12> best{};
    for (int i = 0; i < count; ++i) got[i] = false;
    for_each_neighbour_plane(model, cell, [&](const Vec3& q, const Vec3& nn) {
        for (int i = 0; i < count; ++i) {
            if (!(exits[i] ? nn[axes[i]] > 0.0 : nn[axes[i]] < 0.0)) continue;
            const double r = std::abs(normal_dot(nn, points[i] - q));
            if (!(r <= kBorrowReach)) continue;
            if (!got[i] || r < best[i]) {
                got[i] = true;
                best[i] = r;
                normals[i] = nn;
            }
        }
    });
    int matched = 0;
    for (int i = 0; i < count; ++i)
        if (got[i]) ++matched;
    return matched;
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

const TileContourer::CellVertices& TileContourer::cell_vertices(const Node& cell) {
    const std::size_t idx = static_cast<std::size_t>(cell[0] - cache_lo_[0]) +
                            kCacheSpan * (static_cast<std::size_t>(cell[1] - cache_lo_[1]) +
                                          kCacheSpan * static_cast<std::size_t>(cell[2] - cache_lo_[2]));
    CellVertices& cv = cache_[idx];
    if (cv.stamp != stamp_) {
        const int cfg = occ_.config(cell);
        const CellCase& cc = cell_cases()[cfg];
        std::array<Vec3, kMaxComponents> sum{};
        std::array<int, kMaxComponents> count{};
        std::array<Vec3, 12> point{};
        std::array<std::uint8_t, 12> mat{};
        std::array<int, 12> owner{}, axis{}, edge{};
        std::array<bool, 12> exit{};  // the crossing's start node is inside (it leaves material going +axis)
        std::array<const EdgeSample*, 12> sample{};  // the crossing's cached sample (normal, has_normal)
        int crossings = 0;
        for (int e = 0; e < 12; ++e) {
            const int comp = cc.edge_component[e];
            if (comp < 0) continue;
            const int corner = edge_corners(e)[0], a = e / 4;
            const Node p{cell[0] + (corner & 1), cell[1] + ((corner >> 1) & 1), cell[2] + ((corner >> 2) & 1)};
            const EdgeSample& es = edge_sample(p, a, ((cfg >> corner) & 1) != 0);
            const EdgeCrossing& x = es.crossing;
            sample[crossings] = &es;
            point[crossings] = crossing_point(p, a, x);
            mat[crossings] = x.material;
            axis[crossings] = a;
            edge[crossings] = e;
            exit[crossings] = ((cfg >> corner) & 1) != 0;
            owner[crossings++] = comp;
            sum[comp] += point[crossings - 1];
            ++count[comp];
        }
        const Vec3 lo(cell[0], cell[1], cell[2]);
        std::array<double, kMaxComponents> best_d2{};
        // Per crossing: has a normal, from a crease's flat side, the normal (a component without any may borrow some).
        std::array<bool, 12> hn{}, cr{}, lone{};
        std::array<Vec3, 12> nv{};
        for (int i = 0; i < crossings; ++i) {
            hn[i] = sample[i]->has_normal;
            cr[i] = sample[i]->crease;
            lone[i] = sample[i]->one_sided;
            nv[i] = sample[i]->normal;
        }
        for (int comp = 0; comp < cc.components; ++comp) {
            // The component's crossings in ascending edge order, with their normals; when some have a normal
            // and others not, those others take the normal of the plane fitted to all of them (fit_normal).
            // A normal from the flat side of a crease counts in a component where no crossing has a normal of
            // its own kind. Beside such ordinary normals it counts only when it makes an acute angle with each of
            // them (crease_normal_fits) and the vertex placed with it stays within kCreaseResidual of each of their
            // tangent planes; else the vertex is placed without the crease normals. A crossing at a crease lies
            // on both faces: beside a cut meeting the flat face at a rim in the cell, the flat face's plane keeps
            // the vertex on the rim; beside a cut that undercuts the flat face, normals read across the flat
            // face's edge, or a flat face that only touches the cell, it would carry the vertex across the cut.
            std::array<Vec3, 12> cp{};
            std::array<int, 12> ca{};
            std::array<bool, 12> ce{};
            int nc = 0, plain = 0;
            for (int i = 0; i < crossings; ++i)
                if (owner[i] == comp && hn[i] && !cr[i]) ++plain;
            bool agree = true;
            for (int i = 0; i < crossings; ++i)
                for (int j = 0; j < crossings; ++j)
                    if (owner[i] == comp && owner[j] == comp && hn[i] && cr[i] &&
                        hn[j] && !cr[j] && !crease_normal_fits(nv[i], nv[j]))
                        agree = false;
            int creased = 0;
            for (int i = 0; i < crossings; ++i)
                if (owner[i] == comp && hn[i] && cr[i]) ++creased;
            for (int i = 0; i < crossings; ++i)
                if (owner[i] == comp) {
                    cp[nc] = point[i];
                    ca[nc] = axis[i];
                    ce[nc++] = exit[i];
                }
            const Vec3 mass = sum[comp] / static_cast<double>(count[comp]);
            // No normal at all (kBorrowReach): the face-adjacent cells' crossing normals, matched per crossing.
            // Normals that all took a slope from one side alone, a single one or, without crease normals, one beside a
            // crossing without a normal on a parallel edge of the cell (kBorrowWrongCos): the crossings without one
            // borrow when the normal borrowed for one of the own normals' crossings disagrees with it; the own normals
            // are kept.
            bool borrowed = false;
            // Edge bit masks of the component's crossings, those with a normal and those with a one-sided one; a
            // crossing without a normal on a parallel edge of the cell beside an own normal's (the fin's other wall)
            // is `beside` (edges 4a + k and 4a + (k ^ 1), 4a + (k ^ 2)).
            unsigned own_edges = 0, with_normal = 0, one_sided = 0;
            for (int i = 0; i < crossings; ++i)
                if (owner[i] == comp) {
                    own_edges |= 1u << edge[i];
                    if (hn[i]) with_normal |= 1u << edge[i];
                    if (hn[i] && lone[i]) one_sided |= 1u << edge[i];
                }
            bool beside = false;
            for (unsigned rest = with_normal; rest != 0; rest &= rest - 1) {
                const int e = std::countr_zero(rest), a = e / 4, k = e & 3;
                const unsigned adjacent = (1u << (4 * a + (k ^ 1))) | (1u << (4 * a + (k ^ 2)));
                if ((own_edges & ~with_normal & adjacent) != 0) beside = true;
            }
            const bool all_lone = one_sided == with_normal;
            const bool suspect =
                plain + creased == 0 || (all_lone && (plain + creased == 1 || (creased == 0 && beside)));
            if (suspect) {
                std::array<Vec3, 12> bn{};
                std::array<bool, 12> bg{};
                if (borrowed_normals(*model_, cell, cp.data(), ca.data(), ce.data(), nc, bn.data(), bg.data()) > 0) {
                    bool wrong = plain + creased == 0;
                    for (int i = 0, m = 0; i < crossings; ++i)
                        if (owner[i] == comp) {
                            if (hn[i] && bg[m] && normal_dot(bn[m], nv[i]) < kBorrowWrongCos) wrong = true;
                            ++m;
                        }
                    for (int i = 0, m = 0; wrong && i < crossings; ++i)
                        if (owner[i] == comp) {
                            if (!hn[i] && bg[m]) {
                                hn[i] = true;
                                cr[i] = false;
                                nv[i] = bn[m];
                                borrowed = true;
                            }
                            ++m;
                        }
                }
            }
            // The QEF vertex with or without the crease normals (see above).
            // `extra`: one more plane (point, normal) after the component's, or nullptr.
            auto place = [&](bool with_crease, QefOutcome& how, const Vec3* extra = nullptr, double sheet_cos = kOpposedNormalCos) {
                std::array<bool, 12> use{};
                int own = 0, first = -1;
                for (int i = 0; i < crossings; ++i)
                    if (owner[i] == comp) {
                        use[i] = hn[i] && (with_crease || !cr[i]);
                        if (use[i] && first < 0) first = i;
                    }
                // Two facing walls of a sheet thinner than the cell (normals nearly opposite): one vertex cannot
                // lie on both, so it lies on the wall with more normals (ties: the first crossing's wall).
                bool sheet = false;
                for (int i = 0; i < crossings; ++i)
                    for (int j = i + 1; j < crossings; ++j)
                        if (owner[i] == comp && owner[j] == comp && use[i] && use[j] &&
                            normal_dot(nv[i], nv[j]) < sheet_cos)
                            sheet = true;
                if (sheet) {
                    int same = 0, other = 0;
                    for (int i = 0; i < crossings; ++i)
                        if (owner[i] == comp && use[i]) ++(normal_dot(nv[i], nv[first]) >= 0.0 ? same : other);
                    const bool keep_first = same >= other;
                    for (int i = 0; i < crossings; ++i)
                        if (owner[i] == comp && use[i] && (normal_dot(nv[i], nv[first]) >= 0.0) != keep_first)
                            use[i] = false;
                }
                for (int i = 0; i < crossings; ++i)
                    if (owner[i] == comp && use[i]) ++own;
                Vec3 fitted(0.0);
                const bool fit = !sheet && own > 0 && own < nc && fit_normal(mass, cp.data(), ca.data(), ce.data(), nc, fitted);
                std::array<Vec3, 13> qp{}, qn{};
                int q = 0;
                for (int i = 0; i < crossings; ++i)
                    if (owner[i] == comp && (use[i] || fit)) {
                        qp[q] = point[i];
                        qn[q++] = use[i] ? nv[i] : fitted;
                    }
                if (extra) {
                    qp[q] = extra[0];
                    qn[q++] = extra[1];
                }
                return qef_vertex(mass, qp.data(), qn.data(), q, lo, &how);
            };
            QefOutcome how;
            Vec3 pos(0.0);
            bool done = false;
            if (plain > 0 && creased > 0 && agree) {
                pos = place(true, how);
                double worst = 0.0;
                for (int i = 0; i < crossings; ++i)
                    if (owner[i] == comp && hn[i] && !cr[i]) {
                        const Vec3 d = pos - point[i];
                        const double r = std::abs((nv[i].x * d.x + nv[i].y * d.y) + nv[i].z * d.z);
                        if (r > worst) worst = r;
                    }
                done = worst <= kCreaseResidual;
            }
            // Borrowed normals may come from both walls of a gap narrower than the cell: of each pair at an obtuse
            // angle, only the wall with more of them is kept (kBorrowSheetCos).
            if (!done) pos = place(plain == 0, how, nullptr, borrowed ? kBorrowSheetCos : kOpposedNormalCos);
            const Vec3 off = pos - mass;
            if (plain >= 2 && normal_dot(off, off) > kCornerFillReach * kCornerFillReach) {
                // Corner fill (kCornerFillReach): a concave crease vertex far behind its crossings' mass point, cut
                // off by a neighbouring cell's tangent plane, is placed again with that plane.
                std::array<Vec3, 12> own{};
                int nown = 0;
                Vec3 nsum(0.0);
                for (int i = 0; i < crossings; ++i)
                    if (owner[i] == comp && hn[i]) {
                        own[nown++] = nv[i];
                        nsum = nsum + nv[i];
                    }
                std::array<Vec3, 2> plane{};
                if (normal_dot(nsum, off) < 0.0 && corner_fill_plane(*model_, cell, pos, mass, own.data(), nown, plane[0], plane[1]))
                    pos = place(done, how, plane.data());
            }
            cv.pos[comp] = pos;
            cv.qef[comp] = static_cast<std::uint8_t>((how.normals > 0 ? kQefNormals : 0) | (how.truncated ? kQefTruncated : 0) |
                                                     (how.rejected ? kQefRejected : 0) | (how.clamped ? kQefClamped : 0));
            best_d2[comp] = -1.0;
        }
        // Nearest crossing of each component (see "vertex materials"; ties: the larger material id).
        for (int i = 0; i < crossings; ++i) {
            const int comp = owner[i];
            const Vec3 d = point[i] - cv.pos[comp];
            const double d2 = glm::dot(d, d);
            if (best_d2[comp] < 0.0 || d2 < best_d2[comp] || (d2 == best_d2[comp] && mat[i] > cv.material[comp])) {
                best_d2[comp] = d2;
                cv.material[comp] = mat[i];
            }
        }
        cv.stamp = stamp_;
    }
    return cv;
}

const TileContourer::EdgeSample& TileContourer::edge_sample(const Node& start, int a, bool start_inside) {
    const std::size_t idx = static_cast<std::size_t>(a) +
                            3 * (static_cast<std::size_t>(start[0] - cache_lo_[0]) +
                                 kEdgeSpan * (static_cast<std::size_t>(start[1] - cache_lo_[1]) +
                                              kEdgeSpan * static_cast<std::size_t>(start[2] - cache_lo_[2])));
    EdgeSample& es = edges_[idx];
    if (es.stamp != stamp_) {
        es.crossing = edge_crossing(*model_, a, start, start_inside);
        es.crease = false;
        es.one_sided = false;
        es.has_normal =
            !es.crossing.fallback && es.crossing.exit == start_inside &&
            crossing_normal(*model_, a, start, start_inside, es.crossing.t, es.normal, &es.crease, &es.one_sided);
        es.stamp = stamp_;
    }
    return es;
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
