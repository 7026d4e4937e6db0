// compute/contour/coarse_levels.cpp - group levels contoured from the model read at a coarser stride, with ring
// and skirt.
#include "compute/contour/coarse_levels.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "compute/mesh/mesh_weld.hpp"
#include "compute/contour/startup_refine.hpp"
#include "compute/model/coarse_lattice.hpp"
#include "compute/parallel/task_pool.hpp"
#include "core/error.hpp"

namespace tridex::compute {

struct CoarseGroupLevels::Depth {
    int stride = 2;
    TriDexel model;
    std::unique_ptr<Contourer> contour;
    // A depth built after the constructor (build_depth) is contoured where its levels are read: its tiles still
    // waiting for their first contour. Null once every tile is contoured (or when the constructor contoured them all).
    std::unique_ptr<StartupRefiner> lazy;
    // Per coarse tile: its mesh and materials as last read, and the contour version they were read at (0: never).
    mutable std::vector<TriMesh> meshes;
    mutable std::vector<std::vector<std::uint8_t>> materials;
    mutable std::vector<std::uint64_t> read_at;

    std::size_t tile_index(const std::array<int, 3>& c) const { return model.tiles.index(c[0], c[1], c[2]); }
    bool in_grid(const std::array<int, 3>& c) const {
        for (int a = 0; a < 3; ++a)
            if (c[a] < 0 || c[a] >= model.tiles.tiles[a]) return false;
        return true;
    }
    // Calls fn(tile index, own, coords) for the coarse tile at `c` (own true) and each of the 26 around it in the grid.
    template <typename Fn>
    void around(const std::array<int, 3>& c, Fn&& fn) const {
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const std::array<int, 3> n{c[0] + dx, c[1] + dy, c[2] + dz};
                    if (in_grid(n)) fn(tile_index(n), dx == 0 && dy == 0 && dz == 0, n);
                }
    }
    // Contours the tiles still waiting for their first contour that the mesh of the coarse tile at `c` and of the 26
    // around it borrow from (each of those tiles and the tiles next to it). Not thread-safe.
    void contour_around(const std::array<int, 3>& c) {
        if (!lazy) return;
        around(c, [&](std::size_t t, bool, const std::array<int, 3>& n) {
            if (!lazy->publishable(t)) lazy->refine_group(model, *contour, 1, {n[0] / 2, n[1] / 2, n[2] / 2});
        });
        if (lazy->done()) lazy.reset();
    }
    // True when the level of the coarse tile at `c` can be read: it and the 26 around it are publishable.
    bool readable_around(const std::array<int, 3>& c) const {
        if (!lazy) return true;
        bool ok = true;
        around(c, [&](std::size_t t, bool, const std::array<int, 3>&) { ok = ok && lazy->publishable(t); });
        return ok;
    }
    const TriMesh& mesh_of(std::size_t t, const std::vector<std::uint8_t>*& mats) const {
        const std::uint64_t v = contour->tile_version(t);
        if (read_at[t] != v) {
            meshes[t] = contour->tile_triangle_count(t) ? contour->tile_mesh(t, materials[t]) : TriMesh{};
            if (meshes[t].triangles.empty()) materials[t].clear();
            read_at[t] = v;
        }
        mats = &materials[t];
        return meshes[t];
    }
};

namespace {

// One end of an interval, as the coarse contour sees it: where it lies on the ray, its material, and its side.
struct IntervalEnd {
    float t;
    std::uint8_t material;
    bool exit;
};

// The ends of intervals [first, last) of `ray`, in order along it (the intervals are sorted and disjoint).
void interval_ends(const std::vector<Interval>& ray, std::size_t first, std::size_t last, std::vector<IntervalEnd>& out) {
    out.clear();
    for (std::size_t i = first; i < last; ++i) {
        out.push_back({ray[i].enter, ray[i].enter_material, false});
        out.push_back({ray[i].exit, ray[i].exit_material, true});
    }
}

// [t0, t1] spanning the ends that are in one list and not the other (an end that moved, appeared, vanished or changed
// material, side or bits, as reread_ray compares intervals): the cells between an end's old and new place change, an
// unchanged end (the far side of an interval the tool only entered) changes nothing around it. Lists that differ
// always give t0 <= t1.
void span_of_changed_ends(const std::vector<IntervalEnd>& a, const std::vector<IntervalEnd>& b, double& t0, double& t1) {
    t0 = 1e300;
    t1 = -1e300;
    const auto take = [&](float t) { t0 = std::min<double>(t0, t), t1 = std::max<double>(t1, t); };
    const auto same_bits = [](float x, float y) { return std::memcmp(&x, &y, sizeof(float)) == 0; };
    std::size_t i = 0, j = 0;
    while (i < a.size() || j < b.size()) {
        if (j == b.size() || (i < a.size() && a[i].t < b[j].t)) {
            take(a[i++].t);
        } else if (i == a.size() || b[j].t < a[i].t) {
            take(b[j++].t);
        } else {  // at the same place
            if (!same_bits(a[i].t, b[j].t) || a[i].material != b[j].material || a[i].exit != b[j].exit) take(a[i].t);
            ++i, ++j;
        }
    }
}

// The directed edges (a, b) of the first `count` triangles of `mesh` whose undirected edge is used once among them
// (open border edges), in triangle order. Linear: each vertex's outgoing edges are listed, and an edge's uses are
// counted in the lists of its two ends.
std::vector<std::array<std::uint32_t, 2>> open_edges(const TriMesh& mesh, std::size_t count) {
    const std::size_t nv = mesh.positions.size();
    std::vector<std::uint32_t> start(nv + 1, 0), to(3 * count);
    for (std::size_t i = 0; i < count; ++i)
        for (const std::uint32_t a : mesh.triangles[i]) ++start[a + 1];
    for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
    std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < count; ++i)
        for (int k = 0; k < 3; ++k) to[next[mesh.triangles[i][k]]++] = mesh.triangles[i][(k + 1) % 3];
    const auto uses = [&](std::uint32_t a, std::uint32_t b) {
        return std::count(to.begin() + start[a], to.begin() + start[a + 1], b);
    };
    std::vector<std::array<std::uint32_t, 2>> out;
    for (std::size_t i = 0; i < count; ++i)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = mesh.triangles[i][k], b = mesh.triangles[i][(k + 1) % 3];
            if (uses(a, b) + uses(b, a) == 1) out.push_back({a, b});
        }
    return out;
}

// The neighbours (TileLodLevel::joins bits) whose coarse tile's mesh holds an open border vertex of the first `own`
// triangles of `mesh`: `around` holds each neighbour's mesh with its bit.
std::uint32_t own_border_neighbours(const TriMesh& mesh, std::size_t own,
                                    const std::vector<std::pair<const TriMesh*, int>>& around) {
    using Point = std::array<double, 3>;
    std::vector<Point> border;  // the open border's vertices, sorted
    Vec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const auto& e : open_edges(mesh, own))
        for (const std::uint32_t v : e) {
            const Vec3& p = mesh.positions[v];
            border.push_back({p.x, p.y, p.z});
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
    if (border.empty()) return 0;
    std::sort(border.begin(), border.end());
    std::uint32_t joins = 0;
    for (const auto& [m, bit] : around)
        for (const Vec3& p : m->positions) {
            if (p.x < lo.x || p.y < lo.y || p.z < lo.z || p.x > hi.x || p.y > hi.y || p.z > hi.z) continue;
            if (std::binary_search(border.begin(), border.end(), Point{p.x, p.y, p.z})) {
                joins |= 1u << bit;
                break;
            }
        }
    return joins;
}

// One coarse ray re-read from the fine model into `scratch`: true when it differs from `ray`, which then takes it
// (`scratch` keeps the old one's storage); [t0, t1] spans every interval end that changed (coarse grid units).
bool reread_ray(const std::vector<Interval>& fine_ray, int stride, std::vector<Interval>& ray,
                std::vector<Interval>& scratch, double& t0, double& t1) {
    coarse_ray(fine_ray, stride, scratch);
    const std::vector<Interval>& next = scratch;
    const auto same = [](const Interval& a, const Interval& b) {
        return std::memcmp(&a.enter, &b.enter, sizeof(float)) == 0 && std::memcmp(&a.exit, &b.exit, sizeof(float)) == 0 &&
               a.enter_material == b.enter_material && a.exit_material == b.exit_material;
    };
    std::size_t front = 0;
    while (front < next.size() && front < ray.size() && same(next[front], ray[front])) ++front;
    if (front == next.size() && front == ray.size()) return false;
    std::size_t back_new = next.size(), back_old = ray.size();
    while (back_new > front && back_old > front && same(next[back_new - 1], ray[back_old - 1])) --back_new, --back_old;
    thread_local std::vector<IntervalEnd> ends_new, ends_old;
    interval_ends(next, front, back_new, ends_new);
    interval_ends(ray, front, back_old, ends_old);
    span_of_changed_ends(ends_new, ends_old, t0, t1);
    ray.swap(scratch);
    return true;
}

}  // namespace

CoarseGroupLevels::CoarseGroupLevels(const TriDexel& fine, const CoarseLevelOptions& options, int first_depth)
    : options_(options) {
    if (options.max_depth < 1 || options.max_depth > 6)
        throw Error("CoarseLevelOptions.max_depth: " + std::to_string(options.max_depth) + " is not in 1..6");
    if (options.min_depth < 1 || options.min_depth > options.max_depth)
        throw Error("CoarseLevelOptions.min_depth: " + std::to_string(options.min_depth) + " is not in 1..max_depth (" +
                    std::to_string(options.max_depth) + ")");
    if (!(std::isfinite(options.error_coarse_cells) && options.error_coarse_cells > 0.0))
        throw Error("CoarseLevelOptions.error_coarse_cells: must be finite and > 0");
    if (!(std::isfinite(options.skirt_coarse_cells) && options.skirt_coarse_cells > 0.0))
        throw Error("CoarseLevelOptions.skirt_coarse_cells: must be finite and > 0");
    if (first_depth == 0) first_depth = options.min_depth;
    if (first_depth < options.min_depth || first_depth > options.max_depth)
        throw Error("CoarseGroupLevels: first depth " + std::to_string(first_depth) + " is not in min_depth..max_depth");
    levels_.resize(static_cast<std::size_t>(options.max_depth - options.min_depth + 1));
    for (int d = first_depth; d <= options.max_depth; ++d) {
        build_depth(fine, d);
        Depth& D = *levels_[static_cast<std::size_t>(d - options.min_depth)];
        D.lazy->finish(D.model, *D.contour);  // the whole coarse model now, on the task pool
        D.lazy.reset();
    }
}

bool CoarseGroupLevels::has_depth(int depth) const {
    return depth >= min_depth() && depth <= max_depth() && levels_[static_cast<std::size_t>(depth - min_depth())];
}

void CoarseGroupLevels::build_depth(const TriDexel& fine, int d) {
    if (d < min_depth() || d > max_depth())
        throw Error("CoarseGroupLevels::build_depth: depth " + std::to_string(d) + " is not in " +
                    std::to_string(min_depth()) + ".." + std::to_string(max_depth()));
    std::unique_ptr<Depth>& slot = levels_[static_cast<std::size_t>(d - min_depth())];
    if (slot) return;
    auto D = std::make_unique<Depth>();
    D->stride = 1 << d;
    D->model = coarse_model(fine, D->stride);
    for (int a = 0; a < 3; ++a)  // one coarse tile is one depth-d group
        if (D->model.tiles.tiles[a] != (fine.tiles.tiles[a] + D->stride - 1) / D->stride)
            throw Error("CoarseGroupLevels: the coarse tiles do not match the depth-" + std::to_string(d) + " groups");
    D->contour = std::make_unique<Contourer>(D->model);
    D->lazy = std::make_unique<StartupRefiner>(D->model, 1, Vec3(0.0));  // takes the tiles to contour from the model
    const std::size_t n = D->model.tiles.count();
    D->meshes.resize(n);
    D->materials.resize(n);
    D->read_at.assign(n, 0);
    slot = std::move(D);
}

CoarseGroupLevels::~CoarseGroupLevels() = default;

const CoarseGroupLevels::Depth& CoarseGroupLevels::at(int depth) const {
    if (depth < min_depth() || depth > max_depth())
        throw Error("CoarseGroupLevels: depth " + std::to_string(depth) + " is not in " + std::to_string(min_depth()) +
                    ".." + std::to_string(max_depth()));
    if (!has_depth(depth)) throw Error("CoarseGroupLevels: depth " + std::to_string(depth) + " is not built yet");
    return *levels_[static_cast<std::size_t>(depth - min_depth())];
}

void CoarseGroupLevels::read_around(std::span<const std::pair<int, std::array<int, 3>>> groups) {
    const std::vector<std::uint8_t>* mats = nullptr;
    for (const auto& [depth, c] : groups) {
        (void)at(depth);  // throws for a depth outside the range or not built
        Depth& D = *levels_[static_cast<std::size_t>(depth - min_depth())];
        D.contour_around(c);
        D.around(c, [&](std::size_t t, bool, const std::array<int, 3>&) { (void)D.mesh_of(t, mats); });
    }
}

bool CoarseGroupLevels::contoured_around(int depth, const std::array<int, 3>& coords) const {
    const Depth& D = at(depth);
    if (!D.in_grid(coords)) throw Error("CoarseGroupLevels: group coordinates out of range");
    return D.readable_around(coords);
}

void CoarseGroupLevels::forget_reads() {
    for (const auto& D : levels_) {
        if (!D) continue;
        for (std::size_t t = 0; t < D->meshes.size(); ++t)
            if (D->read_at[t] != 0) {
                D->meshes[t] = TriMesh{};
                D->materials[t] = {};
                D->read_at[t] = 0;
            }
    }
}

std::size_t CoarseGroupLevels::update(const TriDexel& fine, std::span<const std::uint64_t> changed_tiles, int from_depth) {
    constexpr int kT = TileGrid::kTileCells;
    constexpr int kReach = TriDexel::kDirtyReachCells;
    std::size_t recontoured = 0;
    const auto nx = static_cast<std::uint64_t>(fine.tiles.tiles[0]), ny = static_cast<std::uint64_t>(fine.tiles.tiles[1]);
    std::vector<std::uint64_t> rays;  // one axis's coarse rays to re-read, as u + nu * v
    struct RaySpan {
        bool changed = false;
        double t0 = 0.0, t1 = 0.0;  // the span of the ends that moved, coarse grid units along the ray
    };
    std::vector<RaySpan> spans;  // per entry of `rays`
    std::vector<std::vector<Interval>> scratch(pool_slots());  // one ray's buffer per pool slot
    for (std::size_t k = 0; k < levels_.size(); ++k) {
        if (!levels_[k]) continue;  // built later from the model as it is then
        if (options_.min_depth + static_cast<int>(k) < from_depth) continue;
        Depth& D = *levels_[k];
        const int s = D.stride;
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            const RaySet& fs = fine.sets[a];
            RaySet& cs = D.model.sets[a];
            // The coarse rays through each changed tile and the kDirtyReachCells fine cells around it, each once
            // however many changed tiles it crosses.
            rays.clear();
            for (const std::uint64_t t : changed_tiles) {
                const std::array<int, 3> tc{static_cast<int>(t % nx), static_cast<int>((t / nx) % ny), static_cast<int>(t / (nx * ny))};
                const int lo_b = std::max(0, tc[b] * kT - kReach), hi_b = std::min(fine.lattice.cells[b], (tc[b] + 1) * kT + kReach);
                const int lo_c = std::max(0, tc[c] * kT - kReach), hi_c = std::min(fine.lattice.cells[c], (tc[c] + 1) * kT + kReach);
                for (int v = (lo_c + s - 1) / s; v * s <= hi_c && v < cs.nv && v * s < fs.nv; ++v)
                    for (int u = (lo_b + s - 1) / s; u * s <= hi_b && u < cs.nu && u * s < fs.nu; ++u)
                        rays.push_back(static_cast<std::uint64_t>(u) + static_cast<std::uint64_t>(cs.nu) * static_cast<std::uint64_t>(v));
            }
            std::sort(rays.begin(), rays.end());
            rays.erase(std::unique(rays.begin(), rays.end()), rays.end());
            spans.assign(rays.size(), RaySpan{});
            // Each ray is its own vector, so rays re-read at once never share storage.
            pool_for(rays.size(), 64, [&](const Chunk& ch) {
                for (std::size_t i = ch.first; i < ch.last; ++i) {
                    const int u = static_cast<int>(rays[i] % static_cast<std::uint64_t>(cs.nu));
                    const int v = static_cast<int>(rays[i] / static_cast<std::uint64_t>(cs.nu));
                    RaySpan& r = spans[i];
                    r.changed = reread_ray(fs.ray(u * s, v * s), s, cs.ray(u, v), scratch[ch.slot], r.t0, r.t1);
                }
            });
            // Dirty: the cells around each changed ray's span of moved interval ends.
            for (std::size_t i = 0; i < rays.size(); ++i) {
                if (!spans[i].changed) continue;
                Vec3 p0, p1;
                p0[a] = spans[i].t0, p1[a] = spans[i].t1;
                p0[b] = p1[b] = static_cast<double>(rays[i] % static_cast<std::uint64_t>(cs.nu));
                p0[c] = p1[c] = static_cast<double>(rays[i] / static_cast<std::uint64_t>(cs.nu));
                D.model.mark_dirty_grid(glm::min(p0, p1), glm::max(p0, p1));
            }
        }
        recontoured += D.contour->update(D.model);
    }
    return recontoured;
}

TileLodLevel CoarseGroupLevels::level(int depth, const std::array<int, 3>& coords) const {
    const Depth& D = at(depth);
    if (!D.in_grid(coords)) throw Error("CoarseGroupLevels: group coordinates out of range");
    if (!D.readable_around(coords))
        throw Error("CoarseGroupLevels: the depth-" + std::to_string(depth) + " level of a group not read by read_around()");
    const Lattice& L = D.model.lattice;
    constexpr int kT = TileGrid::kTileCells;
    // The group's box grown by one coarse cell: the ring's triangles have their centroid in it.
    Vec3 glo, ghi;
    for (int a = 0; a < 3; ++a) glo[a] = coords[a] * kT - 1.0, ghi[a] = (coords[a] + 1) * kT + 1.0;
    const Vec3 wlo = L.to_world(glo), whi = L.to_world(ghi);
    // The pieces as one soup (each tile's vertices, its triangles that belong), the group's own tile first, welded
    // where tiles share a vertex. Triangles with two corners at one position are left out here, not by the weld, so
    // that the weld keeps every triangle in order and the own ones stay the first own_soup.
    TriMesh soup;
    std::vector<std::uint8_t> soup_materials;
    std::size_t own_soup = 0;
    std::vector<std::pair<const TriMesh*, int>> neighbours;  // each neighbour's coarse tile mesh, with its joins bit
    const auto take = [&](std::size_t t, bool own) -> const TriMesh& {
        const std::vector<std::uint8_t>* mats = nullptr;
        const TriMesh& m = D.mesh_of(t, mats);
        const auto base = static_cast<std::uint32_t>(soup.positions.size());
        soup.positions.insert(soup.positions.end(), m.positions.begin(), m.positions.end());
        if (mats->empty())
            soup_materials.resize(soup.positions.size(), 0);
        else
            soup_materials.insert(soup_materials.end(), mats->begin(), mats->end());
        for (const auto& tri : m.triangles) {
            const Vec3 &a = m.positions[tri[0]], &b = m.positions[tri[1]], &c = m.positions[tri[2]];
            if (a == b || b == c || c == a) continue;
            if (!own) {
                const Vec3 mid = (a + b + c) / 3.0;
                if (mid.x < wlo.x || mid.y < wlo.y || mid.z < wlo.z || mid.x > whi.x || mid.y > whi.y || mid.z > whi.z)
                    continue;
            }
            soup.triangles.push_back({base + tri[0], base + tri[1], base + tri[2]});
            if (own) ++own_soup;
        }
        return m;
    };
    D.around(coords, [&](std::size_t t, bool own, const std::array<int, 3>&) {
        if (own) take(t, true);
    });
    D.around(coords, [&](std::size_t t, bool own, const std::array<int, 3>& n) {
        if (own) return;
        const TriMesh& m = take(t, false);
        if (!m.triangles.empty())
            neighbours.emplace_back(&m, neighbour_bit(n[0] - coords[0], n[1] - coords[1], n[2] - coords[2]));
    });
    TileLodLevel out;
    std::vector<std::uint32_t> source;
    out.mesh = weld_exact(soup, &source);
    out.materials.reserve(source.size());
    for (const std::uint32_t v : source) out.materials.push_back(soup_materials[v]);
    out.error_m = options_.error_coarse_cells * L.cell_m;
    if (out.mesh.triangles.empty()) return out;
    if (out.mesh.triangles.size() == soup.triangles.size()) {  // else (a corner not finite) it is drawn whole
        out.own_triangles = own_soup;
        out.joins = own_border_neighbours(out.mesh, own_soup, neighbours);
    }
    out.normals = vertex_normals(out.mesh);
    add_skirt(out.mesh, out.materials, out.normals, options_.skirt_coarse_cells * L.cell_m);
    return out;
}

std::size_t add_skirt(TriMesh& mesh, std::vector<std::uint8_t>& materials, std::vector<Vec3>& normals, double depth_m) {
    const std::size_t nv = mesh.positions.size();
    if (materials.size() != nv || normals.size() != nv)
        throw Error("add_skirt: " + std::to_string(materials.size()) + " materials and " + std::to_string(normals.size()) +
                    " normals for " + std::to_string(nv) + " vertices");
    std::vector<std::uint32_t> below(nv, ~std::uint32_t{0});  // border vertex -> its skirt vertex
    const auto lower = [&](std::uint32_t v) {
        if (below[v] == ~std::uint32_t{0}) {
            below[v] = static_cast<std::uint32_t>(mesh.positions.size());
            mesh.positions.push_back(mesh.positions[v] - normals[v] * depth_m);
            materials.push_back(materials[v]);
            normals.push_back(normals[v]);
        }
        return below[v];
    };
    const std::vector<std::array<std::uint32_t, 2>> border = open_edges(mesh, mesh.triangles.size());
    mesh.triangles.reserve(mesh.triangles.size() + 4 * border.size());
    for (const auto& [a, b] : border) {
        const std::uint32_t a2 = lower(a), b2 = lower(b);
        mesh.triangles.push_back({b, a, a2});
        mesh.triangles.push_back({b, a2, b2});
        mesh.triangles.push_back({a, b, a2});  // the other winding: seen from either side
        mesh.triangles.push_back({a2, b, b2});
    }
    return border.size();
}

}  // namespace tridex::compute
