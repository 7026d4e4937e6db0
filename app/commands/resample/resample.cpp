// app/commands/resample/resample.cpp - saved model -> re-sampled onto another resolution -> saved model.
#include "app/commands/resample/resample.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cstdio>

#include "app/scene/session_spec.hpp"
#include "app/support/memory.hpp"
#include "app/support/output_dir.hpp"
#include "app/support/progress.hpp"
#include "compute/contour/surface_move.hpp"
#include "compute/model/tdx_file.hpp"
#include "core/error.hpp"

namespace tridex::app {
namespace {

double mib(std::size_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }

}  // namespace

int parse_resolution(const std::string& text) {
    int n = 0;
    const char* end = text.data() + text.size();
    const auto [p, ec] = std::from_chars(text.data(), end, n);
    if (text.empty() || ec != std::errc() || p != end)
        throw Error("--resolution: must be a whole number of cells, got '" + text + "'");
    if (n < compute::kResampleMinResolution || n > compute::kResampleMaxResolution)
        throw Error("--resolution: must be between " + std::to_string(compute::kResampleMinResolution) + " and " +
                    std::to_string(compute::kResampleMaxResolution) + " cells, got " + text);
    return n;
}

ResampleResult run_resample(const ResampleOptions& o) {
    const int resolution = parse_resolution(o.resolution);
    check_distinct_files({{"--out", o.out}}, {{"MODEL", o.model}});
    check_output_file(o.out, "--out");
    const std::size_t budget = model_memory_budget_bytes();
    compute::TdxModel saved;
    {
        ProgressReporter::Step step = progress().step("loading " + o.model);
        saved = compute::load_tdx(o.model, budget, step.fn());
    }
    ResampleResult r;
    r.bytes_before = compute::resample_bytes_estimate(saved.model, saved.model.lattice);
    compute::TriDexel model;
    {
        ProgressReporter::Step step = progress().step("re-sampling to resolution " + std::to_string(resolution));
        try {  // the new model shares the budget with the old one
            model =
                compute::resample_model(saved.model, resolution, budget - std::min(budget, r.bytes_before), &r.stats);
        } catch (const Error& e) {
            throw Error(o.model + ": " + e.what());
        }
    }
    {
        ProgressReporter::Step step = progress().step("measuring the surface move");
        compute::measure_surface_move(saved.model, model, r.stats);
    }
    {
        ProgressReporter::Step step = progress().step("writing " + o.out);
        compute::save_tdx(o.out, model, saved.to_world, settings_at_resolution(saved.settings_json, resolution), 3, saved.palette);
    }
    const compute::ResampleStats& s = r.stats;
    const auto& c = model.lattice.cells;
    const double dv = s.volume_after_m3 - s.volume_before_m3;
    std::printf(
        "tridex resample: %s (resolution %d, cell %.4g mm) -> %s (resolution %d, %dx%dx%d cells, cell %.4g mm)\n",
        o.model.c_str(), s.resolution_before, 1e3 * s.cell_before_m, o.out.c_str(), s.resolution_after, c[0], c[1],
        c[2], 1e3 * s.cell_after_m);
    std::printf("  volume: %.9g m^3 -> %.9g m^3 (%+.6g m^3, %+.4f%%)\n", s.volume_before_m3, s.volume_after_m3, dv,
                s.volume_before_m3 > 0.0 ? 100.0 * dv / s.volume_before_m3 : 0.0);
    const double coarse_m = std::max(s.cell_before_m, s.cell_after_m);
    std::printf(
        "  largest surface move: %.6g m (%.3f cells of the coarser lattice, %.4g mm; the measure's floor on "
        "this model %.3f cells)\n",
        s.max_surface_move_m, s.max_surface_move_cells, 1e3 * coarse_m, s.surface_move_floor_m / coarse_m);
    std::printf("  memory: about %.1f MiB (was %.1f MiB); rays copied %zu, blended %zu, from the field %zu%s\n",
                mib(s.bytes_after), mib(r.bytes_before), s.rays_copied, s.rays_blended, s.rays_field,
                s.identical ? " (same resolution: copied bit for bit)" : "");
    return r;
}

}  // namespace tridex::app
