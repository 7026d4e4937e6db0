// One session pipeline: `tridex demo`, `tridex replay` and `tridex run --display offscreen` carve the same model bit
// for bit from the same scripted stroke, and write one report.json schema (app/session/report/session_report.cpp's, null where
// a session has no value) whose every key docs/report.md documents.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../test_paths.hpp"
#include "app/session/report/session_report.hpp"
#include "compute/model/tdx_file.hpp"
#include "test_files.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The keys in which two reports differ: at every level where both hold an object, a key one has and the other
// lacks. A null on one side and an object on the other is the same key without a value, not a difference.
void key_differences(const json& a, const json& b, const std::string& at, std::vector<std::string>& out) {
    if (!a.is_object() || !b.is_object()) return;
    for (const auto& [k, v] : a.items()) {
        const std::string path = at.empty() ? k : at + "." + k;
        if (!b.contains(k)) {
            out.push_back(path + " (only in the first)");
            continue;
        }
        key_differences(v, b.at(k), path, out);
    }
    for (const auto& [k, v] : b.items())
        if (!a.contains(k)) out.push_back((at.empty() ? k : at + "." + k) + " (only in the second)");
}

std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& x : v) s += "\n  " + x;
    return s;
}

TEST(ReportSchema, ConformFillsEveryKeyAndViolationsNameTheRest) {
    json j = json::object();
    EXPECT_FALSE(report_schema_violations(j).empty()) << "an empty report lacks every key";
    conform_report(j);
    EXPECT_TRUE(report_schema_violations(j).empty()) << joined(report_schema_violations(j));
    EXPECT_TRUE(j.at("frames").is_null());

    json k = json::object();
    k["sculpt"] = {{"samples", 3}};
    k["surprise"] = 1;
    conform_report(k);
    EXPECT_EQ(k["sculpt"]["samples"], 3);
    EXPECT_TRUE(k["sculpt"].contains("rate_hz")) << "a closed object is completed too";
    const std::vector<std::string> v = report_schema_violations(k);
    ASSERT_EQ(v.size(), 1u) << joined(v);
    EXPECT_NE(v[0].find("surprise"), std::string::npos) << v[0];

    k["sculpt"]["extra_counter"] = 0;
    EXPECT_EQ(report_schema_violations(k).size(), 2u) << "an extra key in a closed object breaks the schema";
    k.erase("command");
    EXPECT_EQ(report_schema_violations(k).size(), 3u);
}

TEST(ReportSchema, EveryKeyIsDocumentedInTheReference) {
    std::ifstream in(fs::path(TRIDEX_SOURCE_DIR) / "docs" / "report.md");
    ASSERT_TRUE(in.good()) << "docs/report.md is missing";
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string doc = ss.str();
    for (const ReportField& f : report_schema())
        EXPECT_NE(doc.find(std::string("`") + f.path + "`"), std::string::npos)
            << "docs/report.md does not document `" << f.path << "` (" << f.meaning << ")";
}

TEST(ReportSchema, DemoReplayAndRunWriteTheSameKeys) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_report_schema";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string images = " --width 64 --height 48 --cpu ";
    const auto demo = test::run_tridex("demo --seconds 1 --resolution 48" + images + "--out " + (dir / "demo").string() +
                                           " --record " + (dir / "demo.trdx").string(),
                                       dir / "demo_log");
    ASSERT_EQ(demo.exit_code, 0) << demo.err;
    const auto replay = test::run_tridex("replay " + (dir / "demo.trdx").string() + images + "--out " +
                                             (dir / "replay").string(),
                                         dir / "replay_log");
    ASSERT_EQ(replay.exit_code, 0) << replay.err;
    const std::string scene = (dir / "scene.json").string();
    std::ofstream(scene) << R"({
  "workpiece": { "mesh": ")" << TRIDEX_ASSETS_DIR << R"(/bunny.off", "resolution": 48, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "stroke": { "duration_s": 0.6, "length_m": 0.04, "depth_m": 0.003, "press_axis": "z" },
  "display": { "preset": "desktop", "stereo": "mono", "resolution": [64, 48] },
  "head": { "provider": "fixed", "position_m": [0.0, 0.05, 0.6] }
})";
    const auto run = test::run_tridex("run " + scene + " --display offscreen --cpu --out " + (dir / "run").string(),
                                      dir / "run_log");
    ASSERT_EQ(run.exit_code, 0) << run.err;

    const json d = test::read_json(dir / "demo" / "report.json");
    const json p = test::read_json(dir / "replay" / "report.json");
    const json r = test::read_json(dir / "run" / "report.json");
    EXPECT_EQ(d["command"], "demo");
    EXPECT_EQ(p["command"], "replay");
    EXPECT_EQ(r["command"], "run");
    for (const json* j : {&d, &p, &r})
        EXPECT_TRUE(report_schema_violations(*j).empty()) << (*j)["command"] << ":" << joined(report_schema_violations(*j));
    std::vector<std::string> diff;
    key_differences(d, r, "", diff);
    EXPECT_TRUE(diff.empty()) << "demo and run reports differ in keys:" << joined(diff);
    diff.clear();
    key_differences(d, p, "", diff);
    EXPECT_TRUE(diff.empty()) << "demo and replay reports differ in keys:" << joined(diff);
    // The same quantities under the same names: the volumes add up in every report.
    for (const json* j : {&d, &p, &r})
        EXPECT_NEAR((*j)["volume_removed_m3"].get<double>(),
                    (*j)["volume_before_m3"].get<double>() - (*j)["volume_after_m3"].get<double>(), 1e-15);
    EXPECT_GT(r["volume_removed_m3"].get<double>(), 0.0) << "the run's stroke carved nothing";
    // Where each sculpted, and why (--cpu here; the device's type decides without it: test_backend_choice).
    for (const json* j : {&d, &p, &r}) {
        EXPECT_EQ((*j)["sculpt"]["backend"], "cpu") << (*j)["command"];
        EXPECT_EQ((*j)["sculpt"]["backend_reason"], "--cpu given") << (*j)["command"];
        EXPECT_EQ((*j)["sculpt_path"], (*j)["sculpt"]["backend"]) << (*j)["command"];
        // The haptic loop's stalls over the whole session, and what the system granted or refused.
        const json& h = (*j)["haptics"];
        EXPECT_LE(h["periods_over_5ms"].get<long>(), h["periods_over_2ms"].get<long>()) << (*j)["command"];
        EXPECT_TRUE(h["realtime_refused"].is_null() || h["realtime_refused"].is_string()) << h["realtime_refused"];
        EXPECT_TRUE(h["memory_lock_refused"].is_null() || h["memory_lock_refused"].is_string());
        if (!h["realtime_refused"].is_null()) {
            EXPECT_FALSE(h["realtime_scheduling"].get<bool>()) << h;
            EXPECT_TRUE(h["reserved_cpu"].is_null()) << "a CPU set aside for an ordinary thread: " << h;
        }
        EXPECT_TRUE(h["reserved_cpu"].is_null() || h["reserved_cpu"].get<int>() >= 0) << h["reserved_cpu"];
        EXPECT_FALSE(h["kernel_preemption"].get<std::string>().empty());
        EXPECT_GE(h["period_us"]["max"].get<double>(), h["period_us"]["p99"].get<double>());
    }
    // The run drew its stroke's changes: each first drawn some time after its tool sample, after its publish.
    const json& lat = r["meshes"]["sample_to_drawn_ms"];
    ASSERT_TRUE(lat.is_object()) << r["meshes"];
    EXPECT_GT(lat["median"].get<double>(), 0.0);
    EXPECT_GE(lat["median"].get<double>(), r["meshes"]["sample_to_published_ms"]["median"].get<double>());
    EXPECT_EQ(d["mesh"]["boundary_edges"], 0);
    EXPECT_EQ(r["mesh"]["boundary_edges"], 0);
    fs::remove_all(dir);
}


// The model a .tdx file holds, as canonical bytes: saved again with no settings and every tile clean, so two sessions
// that differ only in what they recorded about themselves compare equal exactly when their dexels do.
std::string model_bytes(const fs::path& tdx, const fs::path& scratch) {
    compute::TdxModel m = compute::load_tdx(tdx.string(), std::size_t{1} << 30);
    std::fill(m.model.tiles.dirty.begin(), m.model.tiles.dirty.end(), std::uint8_t{0});
    compute::save_tdx(scratch.string(), m.model, m.to_world, "");
    return test::bytes_of(scratch);
}

// A scripted stroke carved through `demo` and through `run --display offscreen`, and each session replayed (free
// running, and the demo's also paced with --realtime): every session's tool-sample stream gives the same model bit for
// bit in the other pipeline, at either pace. (Two live sessions of one stroke
// need not agree with each other: the simulated hand feels the contact forces, which depend on when the sculpt thread
// published the surface, so their sample streams differ in the last bits; the model is a function of the stream.)
TEST(SessionPipeline, DemoRunOffscreenAndReplayCarveTheSameModelBitForBit) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_one_pipeline";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string images = " --width 64 --height 48 --cpu ";
    const auto path = [&](const std::string& name) { return (dir / name).string(); };
    // The demo's stroke at its defaults (an 8 mm ball, a 0.12 m pass 6 mm deep on the bunny's viewer side, stock
    // 0.3 m centred 0.3 m in front of the wall), 1 s long.
    const auto demo = test::run_tridex("demo --seconds 1 --resolution 48" + images + "--out " + path("demo") +
                                           " --record " + path("demo.trdx") + " --save " + path("demo.tdx"),
                                       dir / "demo_log");
    ASSERT_EQ(demo.exit_code, 0) << demo.err;
    // The same stroke and contact written as a scene, run offscreen.
    std::ofstream(path("scene.json")) << R"({
  "workpiece": { "mesh": ")" << TRIDEX_ASSETS_DIR << R"(/bunny.off", "resolution": 48, "stock_m": 0.3, "centre_m": [0.0, 0.0, 0.3] },
  "tool": { "radius_m": 0.008 },
  "haptics": { "static_friction": 0.2, "dynamic_friction": 0.15, "cutting_force": true },
  "stroke": { "duration_s": 1.0, "length_m": 0.12, "depth_m": 0.006, "clearance_m": 0.03, "press_axis": "z" },
  "display": { "preset": "desktop", "stereo": "mono", "resolution": [64, 48] },
  "head": { "provider": "fixed", "position_m": [0.0, 0.15, 0.95] }
})";
    const auto run = test::run_tridex("run " + path("scene.json") + " --display offscreen --device simulated --cpu " +
                                          "--no-journal --out " + path("run") + " --record " + path("run.trdx") +
                                          " --save " + path("run.tdx"),
                                      dir / "run_log");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    for (const char* rec : {"demo", "run"}) {
        const std::string name = std::string(rec) + "_replayed";
        const auto replay = test::run_tridex("replay " + path(std::string(rec) + ".trdx") + images + "--out " + path(name) +
                                                 " --save " + path(name + ".tdx"),
                                             dir / (name + "_log"));
        ASSERT_EQ(replay.exit_code, 0) << rec << ": " << replay.err;
    }
    // A replay runs free (as fast as it sculpts); --realtime paces it as the session ran: the same model either way.
    const auto paced = test::run_tridex("replay " + path("demo.trdx") + images + "--realtime --out " +
                                            path("demo_paced") + " --save " + path("demo_paced.tdx"),
                                        dir / "demo_paced_log");
    ASSERT_EQ(paced.exit_code, 0) << paced.err;
    const std::string d = model_bytes(dir / "demo.tdx", dir / "demo.canonical.tdx");
    const std::string r = model_bytes(dir / "run.tdx", dir / "run.canonical.tdx");
    ASSERT_FALSE(d.empty());
    ASSERT_FALSE(r.empty());
    EXPECT_TRUE(d == model_bytes(dir / "demo_replayed.tdx", dir / "demo_replayed.canonical.tdx"))
        << "replay carved another model than the demo it replays";
    EXPECT_TRUE(r == model_bytes(dir / "run_replayed.tdx", dir / "run_replayed.canonical.tdx"))
        << "replay carved another model than the offscreen run it replays";
    EXPECT_TRUE(d == model_bytes(dir / "demo_paced.tdx", dir / "demo_paced.canonical.tdx"))
        << "the replay paced in real time carved another model than the demo it replays";
    // The exported meshes, contoured from those models, are the same bytes too.
    EXPECT_TRUE(test::bytes_of(dir / "demo" / "sculpted.ply") == test::bytes_of(dir / "demo_replayed" / "sculpted.ply"));
    EXPECT_TRUE(test::bytes_of(dir / "run" / "sculpted.ply") == test::bytes_of(dir / "run_replayed" / "sculpted.ply"));
    // Both live sessions carved the stroke, and carved about the same: one stroke, one pipeline.
    const double removed_demo = test::read_json(dir / "demo" / "report.json")["volume_removed_m3"].get<double>();
    const double removed_run = test::read_json(dir / "run" / "report.json")["volume_removed_m3"].get<double>();
    EXPECT_GT(removed_demo, 0.0);
    EXPECT_NEAR(removed_run, removed_demo, 0.1 * removed_demo);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
