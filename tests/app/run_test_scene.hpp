// tests/app/run_test_scene.hpp - a small scene file for `tridex run` tests (bunny at 48 cells, 96 x 72 eyes).
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace tridex::app::test {

/// A fresh folder under the temp dir named after `name` and the process id (tests run in parallel).
inline std::filesystem::path temp_dir(const std::string& name) {
    const std::filesystem::path d =
        std::filesystem::temp_directory_path() / ("tridex_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

/// Writes scene.json into `dir`: the bundled bunny at 48 cells, 0.12 m, a `stroke_s` second stroke, the desktop
/// display at 96 x 72 px per eye and 60 Hz, the head 0.6 m in front of the screen. Returns its path.
inline std::string write_small_scene(const std::filesystem::path& dir, double stroke_s = 0.5) {
    const std::string path = (dir / "scene.json").string();
    std::ofstream(path) << R"({
  "workpiece": { "resolution": 48, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "stroke": { "duration_s": )" << stroke_s << R"(, "length_m": 0.06, "depth_m": 0.004 },
  "display": { "preset": "desktop", "resolution": [96, 72], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.05, 0.6] }
})";
    return path;
}

/// Writes scene.json into `dir`: a two-pass scene (Peng's moving workspace: a jump between the passes lifts the tool,
/// so two strokes) on the bunny at 48 cells, a 3 s stroke, with `keys` (a JSON array of {"t_s", "press"}) pressed
/// at their device times. Returns its path.
inline std::string write_two_pass_scene(const std::filesystem::path& dir, const std::string& keys) {
    const std::string path = (dir / "scene.json").string();
    std::ofstream(path) << R"({
  "workpiece": { "resolution": 48, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.005 },
  "workspace": { "mode": "peng_moving", "scale": 1.0 },
  "stroke": { "duration_s": 3.0, "length_m": 0.03, "depth_m": 0.003, "press_axis": "y", "passes": 2,
              "moves": ["jump"] },
  "display": { "preset": "desktop", "resolution": [96, 72], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.05, 0.6] },
  "keys": )" << keys << R"(
})";
    return path;
}

}  // namespace tridex::app::test
