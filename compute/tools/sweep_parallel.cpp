// compute/tools/sweep_parallel.cpp - rows of the batch's footprint shared out to std::threads.
#include "compute/tools/sweep_parallel.hpp"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <functional>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

#include "core/thread_name.hpp"

namespace tridex::compute {
namespace {

/// One sweep's span on a row: sweep index (into the grid sweeps) and its u range there.
struct RowSweep {
    std::uint32_t sweep;
    int u_lo, u_hi;
};

/// One row of a ray set's footprint union and its sweeps (in batch order) in the flat RowSweep list.
struct Row {
    int axis, v, u_lo, u_hi;
    std::size_t first, count;
};

/// What one worker did.
struct WorkerResult {
    std::size_t rays_changed = 0;
    std::vector<std::uint8_t> sweep_changed;
    std::exception_ptr error;
};

void work(TriDexel& model, const std::vector<GridSweep>& grid, const ToolTable& tools, const std::vector<Row>& rows,
          const std::vector<RowSweep>& spans, std::atomic<std::size_t>& next, WorkerResult& out) {
    // Counters stay local until the end: WorkerResults sit side by side (one cache line).
    std::size_t changed = 0;
    try {
        std::vector<std::uint8_t> sweep_changed(grid.size(), 0);
        for (std::size_t i = next.fetch_add(1, std::memory_order_relaxed); i < rows.size();
             i = next.fetch_add(1, std::memory_order_relaxed)) {
            const Row& r = rows[i];
            RaySet& set = model.sets[r.axis];
            for (int u = r.u_lo; u <= r.u_hi; ++u) {
                std::vector<Interval>& ray = set.ray(u, r.v);
                for (std::size_t k = r.first; k < r.first + r.count; ++k) {
                    const RowSweep& s = spans[k];
                    if (u < s.u_lo || u > s.u_hi) continue;
                    if (apply_sweep_to_ray(grid[s.sweep], r.axis, u, r.v, ray, static_cast<float>(model.lattice.cells[r.axis]), tools)) {
                        ++changed;
                        sweep_changed[s.sweep] = 1;
                    }
                }
            }
        }
        out.sweep_changed = std::move(sweep_changed);
        out.rays_changed = changed;
    } catch (...) {
        out.error = std::current_exception();
        next.store(rows.size(), std::memory_order_relaxed);  // stop the others early
    }
}

}  // namespace

BooleanStats apply_sweeps_parallel(TriDexel& model, std::span<const Sweep> batch, int threads) {
    BooleanStats stats;
    const GridBatch converted = to_grid_batch(model.lattice, batch);  // throws before anything changes
    const std::vector<GridSweep>& grid = converted.sweeps;
    const std::vector<std::size_t>& source = converted.source;
    if (grid.empty()) return stats;

    // Rows of each set's footprint union, each with the sweeps covering it in batch order.
    std::vector<Row> rows;
    std::vector<RowSweep> spans;
    struct Footprint {
        bool any;
        int u_lo, u_hi, v_lo, v_hi;
    };
    std::vector<Footprint> fp(grid.size());
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = model.sets[a];
        int v_min = set.nv, v_max = -1;
        for (std::size_t s = 0; s < grid.size(); ++s) {
            Footprint& f = fp[s];
            f.any = sweep_footprint(grid[s], set, f.u_lo, f.u_hi, f.v_lo, f.v_hi);
            if (!f.any) continue;
            stats.rays_visited += static_cast<std::size_t>(f.u_hi - f.u_lo + 1) * static_cast<std::size_t>(f.v_hi - f.v_lo + 1);
            v_min = std::min(v_min, f.v_lo);
            v_max = std::max(v_max, f.v_hi);
        }
        for (int v = v_min; v <= v_max; ++v) {
            Row row{a, v, set.nu, -1, spans.size(), 0};
            for (std::size_t s = 0; s < grid.size(); ++s) {
                const Footprint& f = fp[s];
                if (!f.any || v < f.v_lo || v > f.v_hi) continue;
                spans.push_back({static_cast<std::uint32_t>(s), f.u_lo, f.u_hi});
                row.u_lo = std::min(row.u_lo, f.u_lo);
                row.u_hi = std::max(row.u_hi, f.u_hi);
            }
            row.count = spans.size() - row.first;
            if (row.count > 0) rows.push_back(row);
        }
    }
    if (rows.empty()) return stats;

    int n = threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency());
    n = std::clamp(n, 1, static_cast<int>(std::min<std::size_t>(rows.size(), 1024)));
    std::atomic<std::size_t> next{0};
    std::vector<WorkerResult> results(static_cast<std::size_t>(n));
    {
        std::vector<std::thread> pool;
        pool.reserve(static_cast<std::size_t>(n - 1));
        for (int t = 1; t < n; ++t) {
            try {
                pool.emplace_back([&, t] {
                    name_this_thread("tridex-sweep");
                    work(model, grid, converted.tools, rows, spans, next, results[static_cast<std::size_t>(t)]);
                });
            } catch (const std::system_error&) {
                break;  // no more threads available: the ones started (and this one) do all rows
            }
        }
        work(model, grid, converted.tools, rows, spans, next, results[0]);
        for (std::thread& t : pool) t.join();
    }
    std::vector<std::uint8_t> changed(grid.size(), 0);
    for (const WorkerResult& r : results) {
        if (r.error) std::rethrow_exception(r.error);
        stats.rays_changed += r.rays_changed;
        if (r.sweep_changed.empty()) continue;  // a worker that was never started
        for (std::size_t s = 0; s < grid.size(); ++s) changed[s] |= r.sweep_changed[s];
    }
    for (std::size_t s = 0; s < grid.size(); ++s)
        if (changed[s]) model.mark_dirty(sweep_bounds(batch[source[s]]));
    return stats;
}

}  // namespace tridex::compute
