// compute/contour/contour_cell.cpp - one cell's dual vertices for TileContourer (see contour_tile.hpp for the method):
// its edge crossings and their normals, the normals a component borrows, and each component's QEF vertex.
#include "compute/contour/contour_tile.hpp"

#include "compute/contour/contour_qef.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace tridex::compute::contour {
namespace {

/// True when a crease normal `crease` (the flat side's, contour::crossing_normal) may stand beside the ordinary
/// normal `plain` in one cell component: they make an acute angle (dot product > 0, summed in a fixed order
/// that the GPU contourer repeats).
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
                Node end = p;
                ++end[a];
                if (in == node_inside(model, end)) continue;
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

/// The sign-change edge crossings of one cell in ascending edge order (at most 12): point (grid units), material,
/// the cell component that owns it, edge axis, cell edge 0..11, whether it leaves material going +axis, and its
/// normal as the edge sample gave it (has one, from a crease's flat side, from one-sided slopes); borrowing
/// (borrow_normals) may give normals to those without one. `sum` and `per_component`: the points' sum and number
/// per component. Lives on the stack for one cell.
struct CellCrossings {
    int count = 0;
    std::array<Vec3, 12> point{};
    std::array<std::uint8_t, 12> material{};
    std::array<int, 12> owner{}, axis{}, edge{};
    std::array<bool, 12> exit{};
    std::array<bool, 12> has_normal{}, crease{}, one_sided{};
    std::array<Vec3, 12> normal{};
    std::array<Vec3, kMaxComponents> sum{};
    std::array<int, kMaxComponents> per_component{};
};

/// One component's share of a cell's crossings (CellCrossings), in ascending edge order: their points, axes and exit
/// flags (fit_normal, borrowed_normals), their mass point, how many have an ordinary (`plain`) or a crease side's
/// (`creased`) normal, and whether every crease normal fits beside every ordinary one (crease_normal_fits).
struct ComponentCrossings {
    int comp = 0;
    int count = 0;
    std::array<Vec3, 12> point{};
    std::array<int, 12> axis{};
    std::array<bool, 12> exit{};
    int plain = 0, creased = 0;
    bool agree = true;
    Vec3 mass{0.0};
};

/// Fills `c` with component `comp`'s share of the cell's crossings `x` (see ComponentCrossings). A normal from the
/// flat side of a crease counts in a component where no crossing has a normal of its own kind. Beside such ordinary
/// normals it counts only when it makes an acute angle with each of them (crease_normal_fits) and the vertex placed
/// with it stays within kCreaseResidual of each of their tangent planes (component_vertex); else the vertex is
/// placed without the crease normals. A crossing at a crease lies on both faces: beside a cut meeting the flat face
/// at a rim in the cell, the flat face's plane keeps the vertex on the rim; beside a cut that undercuts the flat
/// face, normals read across the flat face's edge, or a flat face that only touches the cell, it would carry the
/// vertex across the cut.
void gather_component(const CellCrossings& x, int comp, ComponentCrossings& c) {
    c.comp = comp;
    for (int i = 0; i < x.count; ++i)
        if (x.owner[i] == comp && x.has_normal[i] && !x.crease[i]) ++c.plain;
    for (int i = 0; i < x.count; ++i)
        for (int j = 0; j < x.count; ++j)
            if (x.owner[i] == comp && x.owner[j] == comp && x.has_normal[i] && x.crease[i] && x.has_normal[j] &&
                !x.crease[j] && !crease_normal_fits(x.normal[i], x.normal[j]))
                c.agree = false;
    for (int i = 0; i < x.count; ++i)
        if (x.owner[i] == comp && x.has_normal[i] && x.crease[i]) ++c.creased;
    for (int i = 0; i < x.count; ++i)
        if (x.owner[i] == comp) {
            c.point[c.count] = x.point[i];
            c.axis[c.count] = x.axis[i];
            c.exit[c.count++] = x.exit[i];
        }
    c.mass = x.sum[comp] / static_cast<double>(x.per_component[comp]);
}

/// Borrowing for component c of the cell's crossings x. No normal at all (kBorrowReach): the face-adjacent cells'
/// crossing normals, matched per crossing. Normals that all took a slope from one side alone, a single one or,
/// without crease normals, one beside a crossing without a normal on a parallel edge of the cell (the fin's other
/// wall: edges 4a + k and 4a + (k ^ 1), 4a + (k ^ 2); kBorrowWrongCos): the crossings without one borrow when the
/// normal borrowed for one of the own normals' crossings disagrees with it; the own normals are kept. Writes the
/// borrowed normals into x (as ordinary ones); returns true when it wrote any.
bool borrow_normals(const TriDexel& model, const Node& cell, CellCrossings& x, const ComponentCrossings& c) {
    // Edge bit masks of the component's crossings, those with a normal and those with a one-sided one.
    unsigned own_edges = 0, with_normal = 0, one_sided = 0;
    for (int i = 0; i < x.count; ++i)
        if (x.owner[i] == c.comp) {
            own_edges |= 1u << x.edge[i];
            if (x.has_normal[i]) with_normal |= 1u << x.edge[i];
            if (x.has_normal[i] && x.one_sided[i]) one_sided |= 1u << x.edge[i];
        }
    bool beside = false;
    for (unsigned rest = with_normal; rest != 0; rest &= rest - 1) {
        const int e = std::countr_zero(rest), a = e / 4, k = e & 3;
        const unsigned adjacent = (1u << (4 * a + (k ^ 1))) | (1u << (4 * a + (k ^ 2)));
        if ((own_edges & ~with_normal & adjacent) != 0) beside = true;
    }
    const int known = c.plain + c.creased;
    const bool all_lone = one_sided == with_normal;
    const bool suspect = known == 0 || (all_lone && (known == 1 || (c.creased == 0 && beside)));
    if (!suspect) return false;
    std::array<Vec3, 12> bn{};
    std::array<bool, 12> bg{};
    if (borrowed_normals(model, cell, c.point.data(), c.axis.data(), c.exit.data(), c.count, bn.data(), bg.data()) == 0)
        return false;
    bool wrong = known == 0;
    for (int i = 0, m = 0; i < x.count; ++i)
        if (x.owner[i] == c.comp) {
            if (x.has_normal[i] && bg[m] && normal_dot(bn[m], x.normal[i]) < kBorrowWrongCos) wrong = true;
            ++m;
        }
    bool borrowed = false;
    for (int i = 0, m = 0; wrong && i < x.count; ++i)
        if (x.owner[i] == c.comp) {
            if (!x.has_normal[i] && bg[m]) {
                x.has_normal[i] = true;
                x.crease[i] = false;
                x.normal[i] = bn[m];
                borrowed = true;
            }
            ++m;
        }
    return borrowed;
}

/// The QEF vertex of component c (cell min corner `lo`) with or without the crease normals, and with `extra`, one more
/// plane (point, normal) after the component's, unless nullptr. Two facing walls of a sheet thinner than the cell
/// (a pair of normals with dot product below `sheet_cos`): one vertex cannot lie on both, so it lies on the wall with
/// more normals (ties: the first crossing's wall). When only some crossings have a normal, the others take that of the
/// plane fitted to all of them (fit_normal), except on a sheet. Sets `how` (qef_vertex).
Vec3 place_vertex(const CellCrossings& x, const ComponentCrossings& c, const Vec3& lo, bool with_crease, QefOutcome& how,
                  const Vec3* extra = nullptr, double sheet_cos = kOpposedNormalCos) {
    std::array<bool, 12> use{};
    int own = 0, first = -1;
    for (int i = 0; i < x.count; ++i)
        if (x.owner[i] == c.comp) {
            use[i] = x.has_normal[i] && (with_crease || !x.crease[i]);
            if (use[i] && first < 0) first = i;
        }
    bool sheet = false;
    for (int i = 0; i < x.count; ++i)
        for (int j = i + 1; j < x.count; ++j)
            if (x.owner[i] == c.comp && x.owner[j] == c.comp && use[i] && use[j] &&
                normal_dot(x.normal[i], x.normal[j]) < sheet_cos)
                sheet = true;
    if (sheet) {
        int same = 0, other = 0;
        for (int i = 0; i < x.count; ++i)
            if (x.owner[i] == c.comp && use[i]) ++(normal_dot(x.normal[i], x.normal[first]) >= 0.0 ? same : other);
        const bool keep_first = same >= other;
        for (int i = 0; i < x.count; ++i)
            if (x.owner[i] == c.comp && use[i] && (normal_dot(x.normal[i], x.normal[first]) >= 0.0) != keep_first)
                use[i] = false;
    }
    for (int i = 0; i < x.count; ++i)
        if (x.owner[i] == c.comp && use[i]) ++own;
    Vec3 fitted(0.0);
    const bool fit = !sheet && own > 0 && own < c.count &&
                     fit_normal(c.mass, c.point.data(), c.axis.data(), c.exit.data(), c.count, fitted);
    std::array<Vec3, 13> qp{}, qn{};
    int q = 0;
    for (int i = 0; i < x.count; ++i)
        if (x.owner[i] == c.comp && (use[i] || fit)) {
            qp[q] = x.point[i];
            qn[q++] = use[i] ? x.normal[i] : fitted;
        }
    if (extra) {
        qp[q] = extra[0];
        qn[q++] = extra[1];
    }
    return qef_vertex(c.mass, qp.data(), qn.data(), q, lo, &how);
}

/// Corner fill (kCornerFillReach) of component c's vertex `pos`, placed with the crease normals when `with_crease`:
/// a concave crease vertex far behind its crossings' mass point, cut off by a neighbouring cell's tangent plane
/// (corner_fill_plane), is placed again with that plane (`how` updated); otherwise `pos` stays.
void corner_fill(const TriDexel& model, const Node& cell, const CellCrossings& x, const ComponentCrossings& c,
                 const Vec3& lo, bool with_crease, Vec3& pos, QefOutcome& how) {
    const Vec3 off = pos - c.mass;
    if (!(c.plain >= 2 && normal_dot(off, off) > kCornerFillReach * kCornerFillReach)) return;
    std::array<Vec3, 12> own{};
    int nown = 0;
    Vec3 nsum(0.0);
    for (int i = 0; i < x.count; ++i)
        if (x.owner[i] == c.comp && x.has_normal[i]) {
            own[nown++] = x.normal[i];
            nsum = nsum + x.normal[i];
        }
    std::array<Vec3, 2> plane{};
    if (normal_dot(nsum, off) < 0.0 && corner_fill_plane(model, cell, pos, c.mass, own.data(), nown, plane[0], plane[1]))
        pos = place_vertex(x, c, lo, with_crease, how, plane.data());
}

/// The vertex of component c of `cell` (see TileContourer): its crossings' normals, borrowed ones where it has none
/// or suspect ones (borrow_normals, which writes into x), the QEF vertex with the crease normals when they agree and
/// it stays within kCreaseResidual of every ordinary normal's tangent plane, else without them (borrowed normals may
/// come from both walls of a gap narrower than the cell: of each pair at an obtuse angle only the wall with more of
/// them is kept, kBorrowSheetCos), then the corner fill. Sets `how` for the placement that gave the vertex.
Vec3 component_vertex(const TriDexel& model, const Node& cell, CellCrossings& x, const ComponentCrossings& c, const Vec3& lo,
                      QefOutcome& how) {
    const bool borrowed = borrow_normals(model, cell, x, c);
    Vec3 pos(0.0);
    bool done = false;
    if (c.plain > 0 && c.creased > 0 && c.agree) {
        pos = place_vertex(x, c, lo, true, how);
        double worst = 0.0;
        for (int i = 0; i < x.count; ++i)
            if (x.owner[i] == c.comp && x.has_normal[i] && !x.crease[i]) {
                const Vec3& nv = x.normal[i];
                const Vec3 d = pos - x.point[i];
                const double r = std::abs((nv.x * d.x + nv.y * d.y) + nv.z * d.z);
                if (r > worst) worst = r;
            }
        done = worst <= kCreaseResidual;
    }
    if (!done) pos = place_vertex(x, c, lo, c.plain == 0, how, nullptr, borrowed ? kBorrowSheetCos : kOpposedNormalCos);
    corner_fill(model, cell, x, c, lo, done, pos, how);
    return pos;
}

/// Per component, the material of its crossing nearest to its vertex `pos[comp]` (see TileContourer, "vertex
/// materials"; ties: the larger material id), written to `material` for the `components` components.
void nearest_materials(const CellCrossings& x, int components, const std::array<Vec3, kMaxComponents>& pos,
                       std::array<std::uint8_t, kMaxComponents>& material) {
    std::array<double, kMaxComponents> best_d2{};
    for (int comp = 0; comp < components; ++comp) best_d2[comp] = -1.0;
    for (int i = 0; i < x.count; ++i) {
        const int comp = x.owner[i];
        const Vec3 d = x.point[i] - pos[comp];
        const double d2 = glm::dot(d, d);
        if (best_d2[comp] < 0.0 || d2 < best_d2[comp] || (d2 == best_d2[comp] && x.material[i] > material[comp])) {
            best_d2[comp] = d2;
            material[comp] = x.material[i];
        }
    }
}

}  // namespace

const TileContourer::CellVertices& TileContourer::cell_vertices(const Node& cell) {
    const std::size_t idx = static_cast<std::size_t>(cell[0] - cache_lo_[0]) +
                            kCacheSpan * (static_cast<std::size_t>(cell[1] - cache_lo_[1]) +
                                          kCacheSpan * static_cast<std::size_t>(cell[2] - cache_lo_[2]));
    CellVertices& cv = cache_[idx];
    if (cv.stamp == stamp_) return cv;
    const int cfg = occ_.config(cell);
    const CellCase& cc = cell_cases()[cfg];
    CellCrossings x;
    for (int e = 0; e < 12; ++e) {
        const int comp = cc.edge_component[e];
        if (comp < 0) continue;
        const int corner = edge_corners(e)[0], a = e / 4;
        const Node p{cell[0] + (corner & 1), cell[1] + ((corner >> 1) & 1), cell[2] + ((corner >> 2) & 1)};
        const bool exit = ((cfg >> corner) & 1) != 0;  // the start node is inside: it leaves material going +axis
        const EdgeSample& es = edge_sample(p, a, exit);
        const int i = x.count++;
        x.point[i] = crossing_point(p, a, es.crossing);
        x.material[i] = es.crossing.material;
        x.axis[i] = a;
        x.edge[i] = e;
        x.exit[i] = exit;
        x.owner[i] = comp;
        x.has_normal[i] = es.has_normal;
        x.crease[i] = es.crease;
        x.one_sided[i] = es.one_sided;
        x.normal[i] = es.normal;
        x.sum[comp] += x.point[i];
        ++x.per_component[comp];
    }
    const Vec3 lo(cell[0], cell[1], cell[2]);
    for (int comp = 0; comp < cc.components; ++comp) {
        ComponentCrossings c;
        gather_component(x, comp, c);
        QefOutcome how;
        cv.pos[comp] = component_vertex(*model_, cell, x, c, lo, how);
        cv.qef[comp] = static_cast<std::uint8_t>((how.normals > 0 ? kQefNormals : 0) | (how.truncated ? kQefTruncated : 0) |
                                                 (how.rejected ? kQefRejected : 0) | (how.clamped ? kQefClamped : 0));
    }
    nearest_materials(x, cc.components, cv.pos, cv.material);
    cv.stamp = stamp_;
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

}  // namespace tridex::compute::contour
