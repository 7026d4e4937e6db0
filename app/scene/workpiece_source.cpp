// app/scene/workpiece_source.cpp - mesh or saved model as a session's workpiece.
#include "app/scene/workpiece_source.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <tuple>

#include "app/support/memory.hpp"
#include "app/support/progress.hpp"
#include "app/support/stop_signal.hpp"
#include "app/scene/study_objects.hpp"
#include "app/scene/study_walls.hpp"
#include "app/scene/workpiece_list.hpp"
#include "compute/mesh/mesh_io.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/model/workpiece.hpp"
#include "compute/tools/model_resample.hpp"
#include "core/tri_mesh.hpp"
#include "compute/model/volume.hpp"
#include "core/error.hpp"

namespace tridex::app {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

Workpiece prepare_workpiece(const std::string& mesh_path, int resolution, double stock_m, const Vec3& centre_m) {
    if (resolution < 8 || resolution > 4096)
        throw Error("--resolution: must be between 8 and 4096 cells, got " + std::to_string(resolution));
    ProgressReporter::Step step =
        progress().step("scan-converting " + std::filesystem::path(mesh_path).filename().string() + " at " +
                        std::to_string(resolution) + " cells");
    const TriMesh input = compute::load_closed_mesh(mesh_path);
    const Mat4 to_world = compute::fit_to_stock(input.bounds(), centre_m, stock_m);
    const TriMesh world_mesh = compute::transformed(input, to_world);
    const compute::Lattice lattice = compute::Lattice::around(world_mesh.bounds(), resolution);
    Workpiece wp{mesh_path, resolution, to_world, signed_volume(world_mesh), 0.0, 0.0,
                 compute::TriDexel::empty(lattice, model_memory_budget_bytes())};
    const auto t_scan = std::chrono::steady_clock::now();
    compute::scan_convert(world_mesh, wp.model, step.fn());
    wp.scan_s = seconds_since(t_scan);
    wp.volume_dexel_m3 = compute::dexel_volume_m3(wp.model);
    return wp;
}

Workpiece workpiece_from_model(const std::string& tdx_path) {
    const auto t0 = std::chrono::steady_clock::now();
    ProgressReporter::Step step = progress().step("loading " + tdx_path);
    compute::TdxModel saved = compute::load_tdx(tdx_path, model_memory_budget_bytes(), step.fn());
    Workpiece wp;
    wp.mesh_path = tdx_path;
    const auto& cells = saved.model.lattice.cells;
    wp.resolution = std::max({cells[0], cells[1], cells[2]});
    wp.to_world = saved.to_world;
    wp.palette = saved.palette;
    wp.model = std::move(saved.model);
    std::fill(wp.model.tiles.dirty.begin(), wp.model.tiles.dirty.end(), std::uint8_t{1});
    wp.volume_dexel_m3 = compute::dexel_volume_m3(wp.model);
    wp.volume_mesh_m3 = wp.volume_dexel_m3;
    wp.scan_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return wp;
}

Workpiece prepare_session_workpiece(SessionSpec& spec) {
    const StopEndsSetUp set_up("loading the workpiece");  // nothing to keep yet: a signal stops at once
    if (!spec.study_model.empty()) {
        std::tie(spec.mesh_crc32, spec.mesh_bytes) = file_crc32(spec.mesh_path);  // a replay refuses a changed scene
        const study::StudyScene scene = study::read_study_scene(spec.mesh_path);
        return study::felt_walls(study::Tube(scene.tube), study::study_model(scene, spec.study_model, "study.model"),
                                 scene.path);
    }
    if (spec.model_path.empty()) {
        Workpiece wp = prepare_workpiece(spec.mesh_path, spec.resolution, spec.stock_m, spec.workpiece_centre_m);
        std::tie(spec.mesh_crc32, spec.mesh_bytes) = file_crc32(spec.mesh_path);  // a replay refuses a changed mesh
        return wp;
    }
    std::tie(spec.model_crc32, spec.model_bytes) = file_crc32(spec.model_path);  // a replay refuses a changed model
    Workpiece wp = workpiece_from_model(spec.model_path);
    const compute::Lattice& L = wp.model.lattice;
    spec.resolution = wp.resolution;
    spec.stock_m = std::max(1, wp.resolution - 4) * L.cell_m;  // Lattice::around's 2-cell margins on each end
    spec.workpiece_centre_m = L.bounds().centre();
    if (spec.workpiece_position_m) {  // the scene placed the model's centre elsewhere: a shift from where it was saved
        spec.workpiece_shift_m = *spec.workpiece_position_m - spec.workpiece_centre_m;
        spec.workpiece_position_m.reset();
    }
    if (spec.palette == default_material_palette()) spec.palette = wp.palette;  // a scene's own names win
    spec.mesh_path.clear();
    spec.mesh_crc32 = 0;
    spec.mesh_bytes = 0;
    return wp;
}

std::vector<Workpiece> prepare_more_workpieces(SessionSpec& s) {
    std::vector<Workpiece> out;
    for (std::size_t k = 1; k < workpiece_count(s); ++k) {
        SessionSpec one = spec_for_workpiece(s, k);
        try {
            out.push_back(prepare_session_workpiece(one));
        } catch (const Error& e) {
            throw Error("workpieces[" + std::to_string(k) + "]" + ": " + e.what());
        }
        s.more_workpieces[k - 1] = workpiece_at(one, 0);
    }
    return out;
}

void save_session_model(const std::string& path, const Workpiece& wp, const SessionSpec& spec) {
    // The settings name the lattice saved, which a coarseness change may have made another than the start's.
    compute::save_tdx(path, wp.model, wp.to_world,
                      settings_at_resolution(spec_to_json(spec), compute::lattice_resolution(wp.model.lattice)), 3,
                      spec.palette);
}

namespace {

std::string hex32(std::uint32_t v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%08x", v);
    return buf;
}

// One recorded file against its recorded CRC-32 and size (bytes 0: not recorded, accepted).
void check_file(const std::string& what, const std::string& path, std::uint32_t want_crc, std::uint64_t want_bytes,
                const std::string& source, const std::string& since,
                const std::string& consequence = "it would carve a different model") {
    if (want_bytes == 0) return;
    std::uint32_t crc = 0;
    std::uint64_t bytes = 0;
    try {
        std::tie(crc, bytes) = file_crc32(path);
    } catch (const Error&) {
        throw Error(source + ": the " + what + " " + path + " cannot be read");
    }
    if (crc != want_crc || bytes != want_bytes)
        throw Error(source + ": the " + what + " " + path + " changed since " + since + " (CRC-32 " + hex32(crc) +
                    ", recorded " + hex32(want_crc) + "); " + consequence);
}

}  // namespace

void check_inputs_unchanged(const SessionSpec& s, const std::string& source, const std::string& since) {
    if (s.model_path.empty())
        check_file(s.study_model.empty() ? "workpiece mesh" : "study scene", s.mesh_path, s.mesh_crc32, s.mesh_bytes, source, since);
    else
        check_file("workpiece model", s.model_path, s.model_crc32, s.model_bytes, source, since);
    if (s.tool.kind == ToolKind::kMesh)
        check_file("tool mesh", s.tool_mesh_path, s.tool_mesh_crc32, s.tool_mesh_bytes, source, since);
    for (const ReferenceSpec& r : s.references)
        check_file("reference mesh", r.mesh_path, r.mesh_crc32, r.mesh_bytes, source, since, "it would feel different");
    for (const WorkpieceSpec& w : s.more_workpieces) {  // each further workpiece's mesh or model
        if (w.model_path.empty())
            check_file("workpiece mesh", w.mesh_path, w.mesh_crc32, w.mesh_bytes, source, since);
        else
            check_file("workpiece model", w.model_path, w.model_crc32, w.model_bytes, source, since);
    }
}

}  // namespace tridex::app
