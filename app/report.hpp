// app/report.hpp - the demo's outputs: report.json, haptics.csv and the printed summary.
#pragma once

#include <string>
#include <vector>

#include "app/sculpt_thread.hpp"
#include "compute/lattice.hpp"
#include "core/tri_mesh.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app {

/// Everything report.json says about one demo run (SI units; times in s unless named _us / _ms).
struct DemoReport {
    std::string mesh_path;
    int resolution = 0;
    compute::Lattice lattice;
    Mat4 transform{1.0};              ///< input mesh units -> world metres
    double volume_mesh_m3 = 0.0;      ///< exact volume of the transformed input mesh
    double volume_dexel_m3 = 0.0;     ///< tri-dexel volume before carving
    double volume_after_m3 = 0.0;     ///< tri-dexel volume after carving
    EdgeStats edges;                  ///< of the carved mesh
    std::size_t vertices = 0, triangles = 0;
    const std::vector<haptics::TickRecord>* records = nullptr;
    haptics::LoopStats loop{};
    const SculptStats* sculpt = nullptr;
    std::size_t tiles_initial = 0, tiles_total = 0;
    double scan_s = 0.0, contour_s = 0.0, session_s = 0.0, render_s = 0.0, wall_s = 0.0;
    double tool_radius_m = 0.0, stiffness_n_per_m = 0.0, max_force_n = 0.0;
    std::string device, eye_strategy;
    std::uint32_t validation_messages = 0;
};

/// Writes one row per haptic tick: t_s, hip_x, hip_y, hip_z, proxy_x, proxy_y, proxy_z, fx, fy, fz,
/// contact (metres, newtons, 0/1). Throws tridex::Error "<path>: ..." when it cannot write.
void write_haptics_csv(const std::string& path, const std::vector<haptics::TickRecord>& records);

/// Writes report.json (fields documented in README.md). Throws tridex::Error when it cannot write.
void write_report_json(const std::string& path, const DemoReport& report);

/// Prints a few lines: where the outputs went and the headline numbers.
void print_summary(const DemoReport& report, const std::string& out_dir);

}  // namespace tridex::app
