// bench/soak/bench_soak_script.cpp - the soak's scripted sculptor: a scene whose cursor, keys and head keep working for the
// whole session.
#include "bench/soak/bench_soak.hpp"

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "app/scene/run_scene.hpp"
#include "app/support/json_file.hpp"
#include "core/error.hpp"

namespace tridex::bench {

namespace {

namespace fs = std::filesystem;

// The desk window the soak draws into, px: small, so that lavapipe's frames leave the cores to the sculpting.
constexpr int kWidth = 640;
constexpr int kHeight = 360;
// One cycle of the sculptor, s of device time: choose an operation, one stroke, perhaps undo / redo / tool / save.
constexpr double kCycleS = 5.0;
// The head's loop: three positions about the default head, s between them.
constexpr double kHeadLegS = 20.0;

// The sculptor's repertoire repeats every 6 cycles (30 s): operation, row, direction and tool size, so that the first
// minute has met every stroke it makes and what grows after it is the process's, not a first stroke's buffers.
// The keys pressed in cycle i starting at t0 (device time, s). `keep`: every other stroke is undone and every fourth
// redone, so the model keeps changing; else every stroke is undone (every other one redone and undone again), so the
// model comes back to where it started every cycle.
void add_cycle_keys(nlohmann::json& keys, int i, double t0, bool keep) {
    keys.push_back({{"t_s", t0}, {"press", std::to_string(1 + i % 6)}});  // op.subtract .. op.pull in turn
    if (keep) {
        if (i % 2 == 1) keys.push_back({{"t_s", t0 + 2.6}, {"press", "ctrl+z"}});
        if (i % 4 == 1) keys.push_back({{"t_s", t0 + 3.4}, {"press", "ctrl+y"}});
    } else {
        keys.push_back({{"t_s", t0 + 2.6}, {"press", "ctrl+z"}});
        if (i % 2 == 1) {
            keys.push_back({{"t_s", t0 + 3.0}, {"press", "ctrl+y"}});
            keys.push_back({{"t_s", t0 + 3.4}, {"press", "ctrl+z"}});
        }
    }
    if (i % 6 == 2) keys.push_back({{"t_s", t0 + 4.0}, {"press", "]"}});  // the tool 1.25 times larger for three ...
    if (i % 6 == 5) keys.push_back({{"t_s", t0 + 4.0}, {"press", "["}});  // ... cycles, and back
    if (i % 12 == 11) keys.push_back({{"t_s", t0 + 4.5}, {"press", "ctrl+s"}});  // a save a minute
}

// The cursor in cycle i: over the bunny, press, drag a groove across it (one of three rows, alternating direction),
// let go and move on.
void add_cycle_cursor(nlohmann::json& cursor, int i, double t0) {
    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight, dx = kWidth / 8.0, dy = kHeight / 30.0;
    const double row = cy + 2.0 * dy * (i % 3 - 1);
    const double sign = i % 2 == 0 ? 1.0 : -1.0;
    const double xa = cx - sign * dx, xb = cx + sign * dx;
    cursor.push_back({{"t_s", t0 + 0.1}, {"x_px", xa}, {"y_px", row}, {"buttons", 0}});
    cursor.push_back({{"t_s", t0 + 0.3}, {"x_px", xa}, {"y_px", row}, {"buttons", 1}});
    cursor.push_back({{"t_s", t0 + 1.9}, {"x_px", xb}, {"y_px", row + 0.5 * dy}, {"buttons", 1}});
    cursor.push_back({{"t_s", t0 + 2.0}, {"x_px", xb}, {"y_px", row + 0.5 * dy}, {"buttons", 0}});
    cursor.push_back({{"t_s", t0 + 4.8}, {"x_px", cx}, {"y_px", cy - 3.0 * dy}, {"buttons", 0}});
}

nlohmann::json head_loop() {
    const nlohmann::json positions = {{0.0, 0.05, 0.6}, {0.03, 0.07, 0.58}, {-0.03, 0.04, 0.62}};
    nlohmann::json waypoints = nlohmann::json::array();
    for (std::size_t k = 0; k <= positions.size(); ++k)
        waypoints.push_back({{"t_s", kHeadLegS * static_cast<double>(k)}, {"position_m", positions[k % positions.size()]}});
    return {{"provider", "scripted"}, {"loop", true}, {"waypoints", waypoints}};
}

}  // namespace

std::string write_soak_scene(const std::string& dir, double seconds, int resolution, bool keep) {
    if (!(seconds > 0.0)) throw Error("bench --soak: the session needs a length > 0 s");
    const std::string default_scene = app::default_scene_path();
    const nlohmann::json base = nlohmann::json::parse(std::ifstream(default_scene));
    nlohmann::json scene = base;
    // The scene is written elsewhere: its mesh, named relative to the default scene's folder, by its full path.
    const fs::path mesh = fs::path(default_scene).parent_path() / base.at("workpiece").at("mesh").get<std::string>();
    scene["workpiece"]["mesh"] = fs::absolute(mesh).lexically_normal().string();
    scene["workpiece"]["resolution"] = resolution;
    scene["device"] = {{"driver", "mouse"}};
    scene["stroke"] = "none";
    scene["display"] = {{"preset", "desktop"}, {"stereo", "mono"}, {"resolution", {kWidth, kHeight}}, {"refresh_hz", 60}};
    scene["head"] = head_loop();
    nlohmann::json cursor = nlohmann::json::array(), keys = nlohmann::json::array();
    // A script a cycle longer than the session, so that the sculptor is still working when the time runs out.
    for (int i = 0; kCycleS * i < seconds + kCycleS; ++i) {
        const double t0 = 0.5 + kCycleS * i;
        add_cycle_keys(keys, i, t0, keep);
        add_cycle_cursor(cursor, i, t0);
    }
    scene["cursor"] = cursor;
    scene["keys"] = keys;
    const std::string path = (fs::path(dir) / "soak_scene.json").string();
    app::write_json_file(path, scene);
    return path;
}

}  // namespace tridex::bench
