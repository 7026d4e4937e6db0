// bench/accuracy/bench_accuracy_coarse.cpp - the coarse group levels of a carved model against the exact solid.
#include "bench/accuracy/bench_accuracy_coarse.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <thread>

#include "bench/accuracy/bench_accuracy_metrics.hpp"
#include "compute/contour/coarse_levels.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/dexel_error.hpp"
#include "compute/contour/tile_group_box.hpp"
#include "core/error.hpp"

namespace tridex::bench::accuracy {

namespace {

// One group's measured level.
struct GroupError {
    bool measured = false;  // its level has triangles of its own, or exact-surface samples lie in its box
    std::size_t triangles = 0;
    double vertex_m = 0.0, surface_m = 0.0;
    double dexel_m = 0.0;  // compute::dexel_surface_error of the level in its box
    Vec3 worst_vertex{0.0}, worst_sample{0.0};
    std::size_t samples_missed = 0;
};

// The samples inside each group's box of one depth: CSR over the group grid's linear index.
struct SampleBuckets {
    std::vector<std::size_t> start;  // group -> [start[g], start[g + 1]) in order
    std::vector<std::uint32_t> order;
};

SampleBuckets bucket_samples(const std::vector<Vec3>& samples, const compute::Lattice& lattice, double group_m,
                             const std::array<int, 3>& gdims) {
    const std::size_t groups = static_cast<std::size_t>(gdims[0]) * gdims[1] * gdims[2];
    std::vector<std::size_t> of(samples.size(), groups);  // groups: outside the lattice
    SampleBuckets b;
    b.start.assign(groups + 1, 0);
    for (std::size_t i = 0; i < samples.size(); ++i) {
        std::array<int, 3> c{};
        bool inside = true;
        for (int a = 0; a < 3; ++a) {
            const double u = (samples[i][a] - lattice.origin_m[a]) / group_m;
            c[a] = static_cast<int>(std::floor(u));
            inside = inside && u >= 0.0 && c[a] < gdims[a];
        }
        if (!inside) continue;
        of[i] = static_cast<std::size_t>(compute::grid_index(c, gdims));
        ++b.start[of[i] + 1];
    }
    for (std::size_t g = 0; g < groups; ++g) b.start[g + 1] += b.start[g];
    std::vector<std::size_t> next(b.start.begin(), b.start.end() - 1);
    b.order.resize(b.start[groups]);
    for (std::size_t i = 0; i < samples.size(); ++i)
        if (of[i] < groups) b.order[next[of[i]]++] = static_cast<std::uint32_t>(i);
    return b;
}

// The level of one group against the exact solid.
GroupError measure_group(const compute::TriDexel& model, const compute::CoarseGroupLevels& levels, int depth,
                         const std::array<int, 3>& coords, const ExactSolid& exact, const std::vector<Vec3>& samples,
                         const SampleBuckets& buckets, std::size_t g, double coarse_cell_m) {
    GroupError e;
    const compute::TileLodLevel level = levels.level(depth, coords);
    // A level without triangles of its own (own_triangles 0) holds only neighbours' ring triangles, measured as
    // theirs, and its skirt, which hangs inside the surface by design: only the samples in its box are measured.
    const std::size_t own = level.own_triangles;
    const std::size_t first = buckets.start[g], last = buckets.start[g + 1];
    if (level.mesh.triangles.empty()) {
        e.samples_missed = last - first;
        return e;
    }
    e.measured = own > 0 || last > first;
    e.triangles = own;
    constexpr int kT = compute::TileGrid::kTileCells;
    compute::CellBox box;
    for (int a = 0; a < 3; ++a) {
        box.lo[a] = coords[a] * (1 << depth) * kT;
        box.hi[a] = (coords[a] + 1) * (1 << depth) * kT - 1;
    }
    e.dexel_m = compute::dexel_surface_error(model, box, level.mesh, 2.0 * coarse_cell_m, depth == 1 ? 512 : 256);
    std::vector<bool> seen(level.mesh.positions.size(), false);
    for (std::size_t t = 0; t < own; ++t)
        for (const std::uint32_t v : level.mesh.triangles[t]) {
            if (seen[v]) continue;
            seen[v] = true;
            const double d = std::abs(exact.sdf(level.mesh.positions[v]));
            if (d > e.vertex_m) e.vertex_m = d, e.worst_vertex = level.mesh.positions[v];
        }
    if (last > first) {
        const MeshDistance distance(level.mesh, 2.0 * coarse_cell_m);
        for (std::size_t k = first; k < last; ++k) {
            const Vec3& p = samples[buckets.order[k]];
            const double d = distance.distance(p);
            if (d > e.surface_m) e.surface_m = d, e.worst_sample = p;
        }
    }
    return e;
}

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k];
}

}  // namespace

std::vector<CoarseLevelErrors> coarse_level_errors(const compute::TriDexel& model, const ExactSolid& exact,
                                                   const std::vector<Vec3>& samples, const std::vector<int>& depths,
                                                   int threads) {
    if (threads < 1) throw Error("coarse_level_errors: threads must be >= 1");
    if (depths.empty()) return {};
    for (const int d : depths)
        if (d < 1 || d > 6) throw Error("coarse_level_errors: depth " + std::to_string(d) + " is outside 1..6");
    compute::CoarseLevelOptions options;
    options.min_depth = *std::min_element(depths.begin(), depths.end());
    options.max_depth = *std::max_element(depths.begin(), depths.end());
    compute::CoarseGroupLevels levels(model, options);  // every depth contoured whole
    constexpr int kT = compute::TileGrid::kTileCells;
    std::vector<CoarseLevelErrors> out;
    for (const int depth : depths) {
        CoarseLevelErrors r;
        r.depth = depth;
        r.stride = 1 << depth;
        r.coarse_cell_m = model.lattice.cell_m * r.stride;
        std::array<int, 3> gdims{};
        for (int a = 0; a < 3; ++a) gdims[a] = (model.tiles.tiles[a] + r.stride - 1) >> depth;
        const SampleBuckets buckets = bucket_samples(samples, model.lattice, r.coarse_cell_m * kT, gdims);
        const std::size_t groups = static_cast<std::size_t>(gdims[0]) * gdims[1] * gdims[2];
        std::vector<std::pair<int, std::array<int, 3>>> all(groups);
        for (std::size_t g = 0; g < groups; ++g) all[g] = {depth, compute::grid_coords(g, gdims)};
        levels.read_around(all);  // level() of these only reads from here on, so the threads may call it at once
        std::vector<GroupError> errors(groups);
        std::atomic<std::size_t> next{0};
        std::vector<std::exception_ptr> failed(static_cast<std::size_t>(threads));
        const auto work = [&](std::size_t worker) {
            try {
                for (std::size_t g = next++; g < groups; g = next++)
                    errors[g] =
                        measure_group(model, levels, depth, all[g].second, exact, samples, buckets, g, r.coarse_cell_m);
            } catch (...) {
                failed[worker] = std::current_exception();
                next = groups;  // the others stop too
            }
        };
        std::vector<std::thread> pool;
        for (int i = 1; i < threads; ++i) pool.emplace_back(work, static_cast<std::size_t>(i));
        work(0);
        for (std::thread& t : pool) t.join();
        for (const std::exception_ptr& e : failed)
            if (e) std::rethrow_exception(e);
        std::vector<double> per_group;
        for (const GroupError& e : errors) {
            r.samples_without_level += e.samples_missed;
            if (!e.measured) continue;
            ++r.groups;
            r.triangles += e.triangles;
            if (e.vertex_m > r.max_vertex_m) r.max_vertex_m = e.vertex_m, r.worst_vertex = e.worst_vertex;
            if (e.surface_m > r.max_surface_m) r.max_surface_m = e.surface_m, r.worst_sample = e.worst_sample;
            const double two_sided = std::max(e.vertex_m, e.surface_m);
            per_group.push_back(two_sided);
            if (two_sided > compute::TileSurfaceCache::kStartupErrorCoarseCells * r.coarse_cell_m)
                ++r.over_startup_estimate;
            if (two_sided > options.error_coarse_cells * r.coarse_cell_m) ++r.over_level_estimate;
            if (two_sided > e.dexel_m + 0.5 * model.lattice.cell_m) ++r.over_dexel_estimate;
            r.dexel_excess_max_m = std::max(r.dexel_excess_max_m, two_sided - e.dexel_m);
        }
        r.group_p50_m = quantile(per_group, 0.5);
        r.group_p90_m = quantile(per_group, 0.9);
        r.group_max_m = std::max(r.max_vertex_m, r.max_surface_m);
        out.push_back(r);
    }
    return out;
}

}  // namespace tridex::bench::accuracy
