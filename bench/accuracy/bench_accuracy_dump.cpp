// bench/accuracy/bench_accuracy_dump.cpp - the worst vertices of a run and their cells' crossings (see the header).
#include "bench/accuracy/bench_accuracy_dump.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <vector>

#include "compute/contour/contour_qef.hpp"
#include "compute/contour/contour_sample.hpp"
#include "compute/contour/contour_table.hpp"

namespace tridex::bench::accuracy {
namespace {

/// Node occupancy by the contouring rule (contour_sample.hpp): X ray interval with enter <= i < exit; boundary
/// nodes outside.
bool node_inside(const compute::TriDexel& model, const compute::contour::Node& n) {
    for (int a = 0; a < 3; ++a)
        if (n[a] <= 0 || n[a] >= model.lattice.cells[a]) return false;
    for (const compute::Interval& iv : model.sets[0].ray(n[1], n[2]))
        if (iv.enter <= n[0] && n[0] < iv.exit) return true;
    return false;
}

/// Exact outward normal at p (world m) by central differences of the SDF, step h.
Vec3 exact_normal(const ExactSolid& exact, const Vec3& p, double h) {
    Vec3 g;
    for (int a = 0; a < 3; ++a) {
        Vec3 d(0.0);
        d[a] = h;
        g[a] = exact.sdf(p + d) - exact.sdf(p - d);
    }
    const double l = glm::length(g);
    return l > 0.0 ? g / l : g;
}

/// Prints the interval ends (grid units, "e" enter / "x" exit) within three cells of depth t on the four rays of
/// set a beside node n (u -1, u +1, v -1, v +1).
void print_neighbour_ends(const compute::TriDexel& model, int a, const compute::contour::Node& n, double t) {
    const compute::RaySet& set = model.sets[a];
    const int u = n[(a + 1) % 3], v = n[(a + 2) % 3];
    static constexpr int kDu[4] = {-1, 1, 0, 0}, kDv[4] = {0, 0, -1, 1};
    static constexpr const char* kName[4] = {"u-", "u+", "v-", "v+"};
    std::printf("     ");
    for (int s = 0; s < 4; ++s) {
        const int uu = u + kDu[s], vv = v + kDv[s];
        std::printf(" %s[", kName[s]);
        if (uu >= 0 && vv >= 0 && uu < set.nu && vv < set.nv)
            for (const compute::Interval& iv : set.ray(uu, vv)) {
                if (std::abs(iv.enter - t) <= 3.0) std::printf(" e%.3f", static_cast<double>(iv.enter));
                if (std::abs(iv.exit - t) <= 3.0) std::printf(" x%.3f", static_cast<double>(iv.exit));
            }
        std::printf(" ]");
    }
    std::printf("\n");
}

}  // namespace

void dump_worst_vertices(const compute::TriDexel& model, const TriMesh& mesh, const ExactSolid& exact, int k) {
    const compute::Lattice& L = model.lattice;
    const double h = L.cell_m;
    std::vector<double> err(mesh.positions.size());
    for (std::size_t i = 0; i < err.size(); ++i) err[i] = std::abs(exact.sdf(mesh.positions[i])) / h;
    std::vector<std::size_t> order(err.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return err[x] > err[y]; });
    std::vector<Vec3> shown;
    for (const std::size_t i : order) {
        if (static_cast<int>(shown.size()) >= k) break;
        const Vec3 g = L.to_grid(mesh.positions[i]);
        if (std::any_of(shown.begin(), shown.end(), [&](const Vec3& s) { return glm::length(s - g) < 1.0; })) continue;
        shown.push_back(g);
        const Vec3 en = exact_normal(exact, mesh.positions[i], 1e-3 * h);
        std::printf("vertex (%.3f %.3f %.3f) err %.3f c sdf %+.3f c, exact normal (%+.3f %+.3f %+.3f)\n", g.x, g.y, g.z, err[i],
                    exact.sdf(mesh.positions[i]) / h, en.x, en.y, en.z);
        const compute::contour::Node base{static_cast<int>(std::floor(g.x)), static_cast<int>(std::floor(g.y)),
                                          static_cast<int>(std::floor(g.z))};
        auto config = [&](const compute::contour::Node& n) {
            int bits = 0;
            for (int c = 0; c < 8; ++c)
                if (node_inside(model, {n[0] + (c & 1), n[1] + ((c >> 1) & 1), n[2] + ((c >> 2) & 1)})) bits |= 1 << c;
            return bits;
        };
        // A vertex on a lattice line (an edge crossing or a split-face vertex): the ends of that line's ray.
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            if (g[b] != std::floor(g[b]) || g[c] != std::floor(g[c])) continue;
            const int u = static_cast<int>(g[b]), v = static_cast<int>(g[c]);
            if (u < 0 || v < 0 || u >= model.sets[a].nu || v >= model.sets[a].nv) continue;
            std::printf("  on the axis-%d ray (%d %d):", a, u, v);
            for (const compute::Interval& iv : model.sets[a].ray(u, v))
                if (std::abs(iv.enter - g[a]) <= 3.0 || std::abs(iv.exit - g[a]) <= 3.0)
                    std::printf(" [%.3f %.3f]", static_cast<double>(iv.enter), static_cast<double>(iv.exit));
            std::printf("\n");
        }
        // The cell holding the vertex, and for a vertex on a cell face (clamped there) the cell below that face.
        std::vector<compute::contour::Node> cells{base};
        for (int a = 0; a < 3; ++a)
            if (g[a] == std::floor(g[a])) {
                compute::contour::Node below = base;
                --below[a];
                cells.push_back(below);
            }
        for (const compute::contour::Node& cell : cells) {
        const int cfg = config(cell);
        const compute::contour::CellCase& cc = compute::contour::cell_cases()[cfg];
        if (cc.components == 0 && &cell != &cells.front()) continue;
        std::printf("  cell (%d %d %d) config 0x%02x, %d component(s)\n", cell[0], cell[1], cell[2], cfg, cc.components);
        for (int e = 0; e < 12; ++e) {
            if (cc.edge_component[e] < 0) continue;
            const int corner = compute::contour::edge_corners(e)[0], a = e / 4;
            const compute::contour::Node p{cell[0] + (corner & 1), cell[1] + ((corner >> 1) & 1), cell[2] + ((corner >> 2) & 1)};
            const bool in = ((cfg >> corner) & 1) != 0;
            const compute::contour::EdgeCrossing x = compute::contour::edge_crossing(model, a, p, in);
            const Vec3 q = compute::contour::crossing_point(p, a, x);
            const Vec3 qw = L.to_world(q);
            Vec3 nn(0.0);
            bool crease = false;
            const bool has = !x.fallback && x.exit == in && compute::contour::crossing_normal(model, a, p, in, x.t, nn, &crease);
            const Vec3 xn = exact_normal(exact, qw, 1e-3 * h);
            std::printf("  edge %2d comp %d axis %d at (%.3f %.3f %.3f)%s sdf %+.3f c exact (%+.3f %+.3f %+.3f) est ", e,
                        cc.edge_component[e], a, q.x, q.y, q.z, x.fallback ? " FALLBACK" : "", exact.sdf(qw) / h, xn.x, xn.y, xn.z);
            if (has) std::printf("(%+.3f %+.3f %+.3f)%s\n", nn.x, nn.y, nn.z, crease ? " crease" : "");
            else std::printf("-\n");
            print_neighbour_ends(model, a, p, x.t);
        }
        }
    }
}

}  // namespace tridex::bench::accuracy
