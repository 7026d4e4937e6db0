// tests/chaos/chaos_scene.hpp - the desk session the fault tests run: the mouse as the stylus carving, adding and
// painting across the bunny in 30 strokes over about 10.5 s, with saves, undos, redos and operation changes between
// them (a scripted cursor and keys, docs/formats/scene.md), offscreen.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace tridex::app::test {

/// Seconds the chaos scene's script runs.
inline constexpr double kChaosSceneSeconds = 10.7;

/// Writes the chaos scene to `path` (the bunny at 64 cells, a 6 mm ball, a 192 x 144 desktop view).
inline void write_chaos_scene(const std::filesystem::path& path) {
    const int px[6][2] = {{84, 74}, {104, 82}, {108, 69}, {86, 66}, {92, 85}, {102, 64}};
    std::string cursor, keys;
    double t = 0.2;
    const auto key = [&](double at, const char* press) {
        keys += std::string(keys.empty() ? "" : ",\n") + "    {\"t_s\": " + std::to_string(at) + ", \"press\": \"" +
                press + "\"}";
    };
    const char* ops[3] = {"1", "2", "3"};  // carve, add, paint
    for (int i = 0; i < 30; ++i) {
        const int* a = px[i % 6];
        const int* b = px[(i + 2) % 6];
        const auto point = [&](double at, const int* p, int buttons) {
            cursor += std::string(cursor.empty() ? "" : ",\n") + "    {\"t_s\": " + std::to_string(at) +
                      ", \"x_px\": " + std::to_string(p[0]) + ", \"y_px\": " + std::to_string(p[1]) +
                      ", \"buttons\": " + std::to_string(buttons) + "}";
        };
        point(t, a, 1);
        point(t + 0.25, b, 1);
        point(t + 0.3, b, 0);
        if (i % 5 == 2) key(t + 0.31, ops[(i / 5) % 3]);
        if (i % 3 == 0) key(t + 0.32, "ctrl+s");
        if (i % 4 == 1) key(t + 0.33, "ctrl+z");
        if (i % 8 == 5) key(t + 0.34, "ctrl+y");
        t += 0.35;
    }
    std::ofstream f(path);
    f << "{\n"
      << R"(  "workpiece": { "resolution": 64, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "device": { "driver": "mouse" },
  "stroke": "none",
  "display": { "preset": "desktop", "resolution": [192, 144], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.05, 0.6] },
  "cursor": [
)" << cursor << "\n  ],\n  \"keys\": [\n"
      << keys << "\n  ]\n}\n";
}

}  // namespace tridex::app::test
