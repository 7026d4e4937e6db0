// compute/model/islands.cpp - the contour's pieces of a tri-dexel model in a box: runs of inside lattice nodes along
// the X rays, joined by a union-find, and the intervals of the three sets that hold the small closed ones.
#include "compute/model/islands.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <tuple>

#include "core/error.hpp"

namespace tridex::compute {
namespace {

constexpr std::uint32_t kNone = 0xffffffffu;

// Disjoint sets (path halving, union by size).
class UnionFind {
public:
    explicit UnionFind(std::size_t n) : parent_(n), size_(n, 1u) {
        for (std::size_t i = 0; i < n; ++i) parent_[i] = static_cast<std::uint32_t>(i);
    }
    std::uint32_t find(std::uint32_t a) {
        while (parent_[a] != a) {
            parent_[a] = parent_[parent_[a]];
            a = parent_[a];
        }
        return a;
    }
    void unite(std::uint32_t a, std::uint32_t b) {
        a = find(a);
        b = find(b);
        if (a == b) return;
        if (size_[a] < size_[b]) std::swap(a, b);
        parent_[b] = a;
        size_[a] += size_[b];
    }

private:
    std::vector<std::uint32_t> parent_;
    std::vector<std::uint32_t> size_;
};

// The box as lattice nodes that can be inside (the border's are not), and whether material may go on beyond each
// side (a side inside the lattice's interior nodes).
struct NodeBox {
    std::array<int, 3> lo{}, hi{};
    std::array<bool, 3> open_lo{}, open_hi{};
};

// The inside nodes x_n0 .. x_n1 that one X interval holds on X ray (j, k), within the box.
struct Run {
    int n0 = 0, n1 = 0;
    int j = 0, k = 0;
    std::uint32_t interval = 0;  // index in the ray
};

// One interval of a piece: set, ray index in RaySet::rays, index in the ray.
using IntervalRef = std::tuple<std::uint8_t, std::uint32_t, std::uint32_t>;

// The runs of the X rays through the box, ray by ray (k outer, j inner); first[r] .. first[r + 1] are ray r's.
struct Runs {
    std::vector<Run> runs;
    std::vector<std::uint32_t> first;
    int nj = 0, nk = 0;
    std::size_t ray(const NodeBox& b, int j, int k) const {
        return static_cast<std::size_t>(j - b.lo[1]) + static_cast<std::size_t>(nj) * static_cast<std::size_t>(k - b.lo[2]);
    }
};

Runs collect_runs(const TriDexel& m, const NodeBox& b) {
    Runs r;
    r.nj = b.hi[1] - b.lo[1] + 1;
    r.nk = b.hi[2] - b.lo[2] + 1;
    r.first.reserve(static_cast<std::size_t>(r.nj) * static_cast<std::size_t>(r.nk) + 1);
    for (int k = b.lo[2]; k <= b.hi[2]; ++k) {
        for (int j = b.lo[1]; j <= b.hi[1]; ++j) {
            r.first.push_back(static_cast<std::uint32_t>(r.runs.size()));
            const std::vector<Interval>& ray = m.sets[0].ray(j, k);
            for (std::size_t i = 0; i < ray.size(); ++i) {
                const Interval& iv = ray[i];
                if (!(iv.enter <= iv.exit)) continue;  // NaN or reversed: not a span
                const double first = std::max<double>(std::ceil(static_cast<double>(iv.enter)), b.lo[0]);
                const double last = std::min<double>(std::ceil(static_cast<double>(iv.exit)) - 1.0, b.hi[0]);
                if (first > last) continue;
                r.runs.push_back(Run{static_cast<int>(first), static_cast<int>(last), j, k, static_cast<std::uint32_t>(i)});
            }
        }
    }
    if (r.runs.size() >= kNone) throw Error("find_islands: too many intervals in the box");
    r.first.push_back(static_cast<std::uint32_t>(r.runs.size()));
    return r;
}

// Joins runs whose nodes are lattice neighbours (6-neighbours): on one ray, node ranges next to each other; on
// 4-neighbour rays, a common node index.
void join_runs(const Runs& r, const NodeBox& b, UnionFind& uf) {
    const auto join_rays = [&](std::size_t ra, std::size_t rb) {
        std::uint32_t i = r.first[ra], j = r.first[rb];
        const std::uint32_t ie = r.first[ra + 1], je = r.first[rb + 1];
        while (i < ie && j < je) {
            if (r.runs[i].n0 <= r.runs[j].n1 && r.runs[j].n0 <= r.runs[i].n1) uf.unite(i, j);
            if (r.runs[i].n1 < r.runs[j].n1) ++i; else ++j;
        }
    };
    for (int k = b.lo[2]; k <= b.hi[2]; ++k) {
        for (int j = b.lo[1]; j <= b.hi[1]; ++j) {
            const std::size_t ra = r.ray(b, j, k);
            for (std::uint32_t i = r.first[ra] + 1; i < r.first[ra + 1]; ++i)
                if (r.runs[i].n0 == r.runs[i - 1].n1 + 1) uf.unite(i - 1, i);
            if (j < b.hi[1]) join_rays(ra, r.ray(b, j + 1, k));
            if (k < b.hi[2]) join_rays(ra, r.ray(b, j, k + 1));
        }
    }
}

// Index of the interval of `ray` holding depth t (enter <= t < exit), kNone when none does. O(log intervals).
std::uint32_t holding(const std::vector<Interval>& ray, double t) {
    const auto it = std::upper_bound(ray.begin(), ray.end(), t, [](double x, const Interval& iv) { return x < iv.enter; });
    if (it == ray.begin()) return kNone;
    const std::size_t i = static_cast<std::size_t>(it - ray.begin()) - 1;
    return t < ray[i].exit ? static_cast<std::uint32_t>(i) : kNone;
}

// The intervals of the three sets holding the nodes of `runs` (one piece), sorted and without repeats.
std::vector<IntervalRef> piece_intervals(const TriDexel& m, const std::vector<const Run*>& runs) {
    std::vector<IntervalRef> refs;
    const RaySet &xs = m.sets[0], &ys = m.sets[1], &zs = m.sets[2];
    for (const Run* run : runs) {
        refs.emplace_back(0, static_cast<std::uint32_t>(run->j + xs.nu * run->k), run->interval);
        for (int i = run->n0; i <= run->n1; ++i) {
            const std::uint32_t y = holding(ys.ray(run->k, i), run->j);  // Y ray (z_k, x_i) holding y_j
            if (y != kNone) refs.emplace_back(1, static_cast<std::uint32_t>(run->k + ys.nu * i), y);
            const std::uint32_t z = holding(zs.ray(i, run->j), run->k);  // Z ray (x_i, y_j) holding z_k
            if (z != kNone) refs.emplace_back(2, static_cast<std::uint32_t>(i + zs.nu * run->j), z);
        }
    }
    std::sort(refs.begin(), refs.end());
    refs.erase(std::unique(refs.begin(), refs.end()), refs.end());
    return refs;
}

// World box of a piece's intervals.
Aabb box_of(const TriDexel& m, const std::vector<IntervalRef>& refs) {
    Vec3 lo(1e300), hi(-1e300);
    for (const auto& [a, ray, idx] : refs) {
        const RaySet& s = m.sets[a];
        const Interval& iv = s.rays[ray][idx];
        Vec3 l, h;
        l[a] = iv.enter;
        h[a] = iv.exit;
        l[(a + 1) % 3] = h[(a + 1) % 3] = static_cast<double>(ray % static_cast<std::uint32_t>(s.nu));
        l[(a + 2) % 3] = h[(a + 2) % 3] = static_cast<double>(ray / static_cast<std::uint32_t>(s.nu));
        lo = glm::min(lo, l);
        hi = glm::max(hi, h);
    }
    return Aabb{m.lattice.to_world(lo), m.lattice.to_world(hi)};
}

// The rays holding `refs` (sorted), each without those intervals.
std::vector<RayImage> images_without(const TriDexel& m, const std::vector<IntervalRef>& refs) {
    std::vector<RayImage> out;
    std::size_t i = 0;
    while (i < refs.size()) {
        const auto [a, ray, first] = refs[i];
        std::size_t e = i;
        while (e < refs.size() && std::get<0>(refs[e]) == a && std::get<1>(refs[e]) == ray) ++e;
        const std::vector<Interval>& src = m.sets[a].rays[ray];
        RayImage img{a, ray, {}};
        img.intervals.reserve(src.size() - (e - i));
        std::size_t r = i;
        for (std::uint32_t k = 0; k < src.size(); ++k) {
            if (r < e && std::get<2>(refs[r]) == k) {
                ++r;
                continue;
            }
            img.intervals.push_back(src[k]);
        }
        out.push_back(std::move(img));
        i = e;
    }
    return out;
}

}  // namespace

double speck_volume_m3(double tool_radius_m) {
    if (!std::isfinite(tool_radius_m) || tool_radius_m <= 0.0) return 0.0;
    return 4.0 / 3.0 * std::numbers::pi * tool_radius_m * tool_radius_m * tool_radius_m;
}

IslandSearch find_islands(const TriDexel& model, const Aabb& box_m, const IslandOptions& options) {
    if (!std::isfinite(options.max_volume_m3) || options.max_volume_m3 < 0.0)
        throw Error("find_islands: max_volume_m3 must be finite and >= 0");
    IslandSearch out;
    if (box_m.empty()) return out;
    if (!is_finite(box_m.lo) || !is_finite(box_m.hi)) throw Error("find_islands: the box must be finite");
    const Lattice& l = model.lattice;
    NodeBox b;
    const Vec3 glo = l.to_grid(box_m.lo), ghi = l.to_grid(box_m.hi);
    for (int a = 0; a < 3; ++a) {
        const double first = 1.0, last = l.cells[a] - 1.0;  // the interior nodes
        const double lo = std::max(first, std::floor(glo[a])), hi = std::min(last, std::ceil(ghi[a]));
        if (lo > hi) return out;  // beside the lattice, or a lattice without interior nodes
        b.lo[a] = static_cast<int>(lo);
        b.hi[a] = static_cast<int>(hi);
        b.open_lo[a] = b.lo[a] > 1;
        b.open_hi[a] = b.hi[a] < l.cells[a] - 1;
    }
    const Runs r = collect_runs(model, b);
    if (r.runs.empty()) return out;
    UnionFind uf(r.runs.size());
    join_runs(r, b, uf);

    // Pieces: their runs (by root, in run order), nodes, X lengths and box, and whether one touches an open side.
    struct Acc {
        std::vector<const Run*> runs;
        std::size_t nodes = 0;
        double length = 0.0;
        Vec3 lo{1e300}, hi{-1e300};
        bool open = false;
    };
    std::vector<std::uint32_t> piece_of(r.runs.size(), kNone);
    std::vector<Acc> acc;
    for (std::uint32_t i = 0; i < r.runs.size(); ++i) {
        const Run& run = r.runs[i];
        const std::uint32_t root = uf.find(i);
        if (piece_of[root] == kNone) {
            piece_of[root] = static_cast<std::uint32_t>(acc.size());
            acc.emplace_back();
        }
        Acc& p = acc[piece_of[root]];
        const Interval& iv = model.sets[0].ray(run.j, run.k)[run.interval];
        p.runs.push_back(&run);
        p.nodes += static_cast<std::size_t>(run.n1 - run.n0 + 1);
        p.length += static_cast<double>(iv.exit) - static_cast<double>(iv.enter);
        p.lo = glm::min(p.lo, Vec3(iv.enter, run.j, run.k));
        p.hi = glm::max(p.hi, Vec3(iv.exit, run.j, run.k));
        out.nodes += static_cast<std::size_t>(run.n1 - run.n0 + 1);
        p.open = p.open || (run.n0 == b.lo[0] && b.open_lo[0]) || (run.n1 == b.hi[0] && b.open_hi[0]) ||
                 (run.j == b.lo[1] && b.open_lo[1]) || (run.j == b.hi[1] && b.open_hi[1]) ||
                 (run.k == b.lo[2] && b.open_lo[2]) || (run.k == b.hi[2] && b.open_hi[2]);
    }
    out.pieces = acc.size();

    // The closed pieces, largest first; the specks' intervals of all three sets.
    const double h3 = l.cell_m * l.cell_m * l.cell_m;
    std::vector<std::pair<IslandPiece, std::size_t>> closed;
    for (std::size_t p = 0; p < acc.size(); ++p) {
        if (acc[p].open) continue;
        IslandPiece piece;
        piece.nodes = acc[p].nodes;
        piece.volume_m3 = acc[p].length * h3;
        piece.box_m = Aabb{l.to_world(acc[p].lo), l.to_world(acc[p].hi)};
        closed.emplace_back(piece, p);
    }
    std::stable_sort(closed.begin(), closed.end(), [](const auto& x, const auto& y) { return x.first.volume_m3 > y.first.volume_m3; });
    std::vector<IntervalRef> speck_refs;
    for (const auto& [piece, p] : closed) {
        out.closed.push_back(piece);
        if (!(piece.volume_m3 < options.max_volume_m3)) continue;
        out.specks.push_back(piece);
        out.speck_volume_m3 += piece.volume_m3;
        const std::vector<IntervalRef> refs = piece_intervals(model, acc[p].runs);
        const Aabb box = box_of(model, refs);
        out.speck_box_m.add(box.lo);
        out.speck_box_m.add(box.hi);
        speck_refs.insert(speck_refs.end(), refs.begin(), refs.end());
    }
    std::sort(speck_refs.begin(), speck_refs.end());
    speck_refs.erase(std::unique(speck_refs.begin(), speck_refs.end()), speck_refs.end());
    out.rays = images_without(model, speck_refs);
    return out;
}

}  // namespace tridex::compute
