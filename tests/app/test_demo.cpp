// Integration test: `tridex demo` end to end on a short stroke, and refusal of bad meshes.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include <sstream>
#include <string>
#include "../test_paths.hpp"
#include "test_files.hpp"

#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

namespace {

using tridex::app::test::run_tridex;
using RunResult = tridex::app::test::ExeResult;

namespace fs = std::filesystem;

// A session ended by a signal stops its threads, writes every output and exits 128 + the signal number.
TEST(Signals, SigtermEndsARunCleanlyAndSigintADemo) {
    const fs::path out = fs::path(testing::TempDir()) / "tridex_sigterm";
    fs::remove_all(out);
    // `timeout --preserve-status` sends the signal after 6 s and exits with the program's own status.
    const std::string cmd = "timeout --preserve-status -s TERM 6 " + std::string(TRIDEX_EXE) +
                            " run --display offscreen --frames 1000000 --out " + out.string() + " > " + out.string() + ".log 2>&1";
    int status = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 143);
    for (const char* f : {"left.png", "right.png", "output.png", "sculpted.ply", "report.json"})
        EXPECT_TRUE(fs::is_regular_file(out / f)) << f;
    std::ifstream rf(out / "report.json");
    const nlohmann::json rep = nlohmann::json::parse(rf);
    EXPECT_EQ(rep["notes"][0], "ended: SIGTERM received");
    EXPECT_EQ(rep["haptics"]["device_status"]["state"], "closed");

    const fs::path dout = fs::path(testing::TempDir()) / "tridex_sigint";
    fs::remove_all(dout);
    const std::string dcmd = "timeout --preserve-status -s INT 5 " + std::string(TRIDEX_EXE) +
                             " demo --seconds 60 --resolution 64 --width 64 --height 48 --out " + dout.string() +
                             " > " + dout.string() + ".log 2>&1";
    status = std::system(dcmd.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 130);
    std::ifstream df(dout / "report.json");
    ASSERT_TRUE(df.good());
    const nlohmann::json drep = nlohmann::json::parse(df);
    EXPECT_EQ(drep["stopped_by"], "SIGINT");
    EXPECT_LT(drep["ticks"].get<int>(), 60000);  // ended early
    EXPECT_TRUE(fs::is_regular_file(dout / "sculpted.ply"));
}

// Bad output locations and command lines are refused up front: exit 2, one line naming the flag.
TEST(BadInput, OutputsAndCommandLinesAreRefusedWithOneLine) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_bad_input";
    fs::create_directories(dir);
    std::ofstream(dir / "a_file") << "x";
    std::ofstream(dir / "huge_scene.json") << "{ \"workpiece\": { \"resolution\": 32,\n                 \"stock_m\": 1e400 } }\n";
    std::ofstream(dir / "gain_scene.json") << "{ \"workspace\": { \"mode\": \"scaling\", \"scale\": 1e-320 } }\n";
    std::ofstream(dir / "sym_scene.json") << "{ \"symmetry\": \"radial:6\" }\n";
    const std::pair<std::string, std::string> cases[] = {
        {"demo --out " + (dir / "a_file").string(), "--out"},
        {"demo --out /dev/full", "--out /dev/full: not a folder"},
        {"demo --record /dev/full --out " + (dir / "o").string(), "--record /dev/full: cannot write"},
        {"demo --record " + dir.string() + " --out " + (dir / "o").string(), "is a folder"},
        {"demo --resolution abc", "--resolution"},
        {"demo --no-such-flag", "no-such-flag"},
        {"run " + dir.string() + " --display offscreen --frames 1 --out " + (dir / "o").string(), "is a folder"},
        {"replay " + (dir / "a_file").string() + " --out /dev/full", "--out /dev/full"},
        {"demo --tool-radius-mm 500 --out " + (dir / "o").string(), "(75 mm), got 500"},
        {"bogus", "unknown command 'bogus'; the commands are demo, "},
        {"--versions", "--versions"},
        {"demo --tool-length-mm 20 --out " + (dir / "o").string(), "--tool-length-mm: only with --tool flat_end"},
        {"demo --falcon-firmware " + (dir / "a_file").string() + " --out " + (dir / "o").string(),
         "--falcon-firmware: only with --device falcon or falcon-emulator"},
        {"demo --device foo", "use omni, wand, 6dof, falcon, falcon-emulator or net:HOST:PORT"},
        {"device-server --device replay", "--device: a device server serves simulated, falcon or falcon-emulator"},
        {"device-server --profile foo", "--profile: unknown profile 'foo'"},
        {"device-server --stroke-seconds -1", "--stroke-seconds: must be between 0.5 and 600"},
        // Outputs that would overwrite each other, or the model the session starts from.
        {"demo --out " + (dir / "o").string() + " --save " + (dir / "o" / "report.json").string(),
         "is also --out's report.json"},
        {"demo --out " + (dir / "o").string() + " --save " + (dir / "same").string() + " --record " +
             (dir / "o" / ".." / "same").string(),
         "--save " + (dir / "same").string() + ": is also --record"},
        {"demo --out " + (dir / "o").string() + " --journal " + (dir / "o" / "sculpted.ply").string(),
         "--journal " + (dir / "o" / "sculpted.ply").string() + ": is also --out's sculpted.ply"},
        {"demo --out " + (dir / "o").string() + " --workpiece " + (dir / "a_file").string() + " --save " +
             (dir / "a_file").string(),
         "is also --workpiece, which the session reads"},
        {"run --display offscreen --frames 1 --out " + (dir / "o").string() + " --record " +
             (dir / "o" / "model.tdx").string(),
         "is also the Ctrl+S model (--out's model.tdx)"},
        // Symmetry: the option and the scene field, each named with the allowed forms.
        {"demo --symmetry w --out " + (dir / "o").string(),
         "--symmetry: bad symmetry 'w'; use off, x, y, z, xy, xz, yz, xyz or radial:N:AXIS (N 2..32, AXIS x, y or z)"},
        {"demo --symmetry radial:40:z --out " + (dir / "o").string(),
         "--symmetry: bad symmetry 'radial:40:z' (N = 40 is outside 2..32)"},
        {"run --symmetry zx --display offscreen --frames 1 --out " + (dir / "o").string(), "--symmetry: bad symmetry 'zx'"},
        {"run " + (dir / "sym_scene.json").string() + " --display offscreen --frames 1 --out " + (dir / "o").string(),
         "sym_scene.json: field 'symmetry': 'radial:6' is not one of off, x, y, z, xy, xz, yz, xyz or radial:N:AXIS"},
        // Numbers: decimal, whole, finite, in range.
        {"demo --seconds 0x10 --out " + (dir / "o").string(), "--seconds: '0x10' is not a decimal number"},
        {"demo --seconds inf --out " + (dir / "o").string(), "--seconds: 'inf' is not a decimal number"},
        {"demo --seconds 1e --out " + (dir / "o").string(), "--seconds: '1e' is not a decimal number"},
        {"demo --seconds . --out " + (dir / "o").string(), "--seconds: '.' is not a decimal number"},
        {"demo --seconds 1.5.2 --out " + (dir / "o").string(), "--seconds: '1.5.2' is not a decimal number"},
        {"demo --seconds +-1 --out " + (dir / "o").string(), "--seconds: '+-1' is not a decimal number"},
        {"demo --width 12.5 --out " + (dir / "o").string(), "--width: '12.5' is not a decimal number (a whole number)"},
        {"demo --width 1e3 --out " + (dir / "o").string(), "--width: '1e3' is not a decimal number (a whole number)"},
        {"demo --static-friction 1e308 --out " + (dir / "o").string(), "--static-friction: must be between 0 and 10, got 1e+308"},
        {"demo --dynamic-friction 0.5 --out " + (dir / "o").string(),
         "--dynamic-friction: must be between 0 and --static-friction (0.2), got 0.5"},
        // Scene files: a number beyond a double's range and a workspace gain out of range, each placed and named.
        {"run " + (dir / "huge_scene.json").string() + " --display offscreen --frames 1 --out " + (dir / "o").string(),
         "huge_scene.json: not valid JSON: number overflow at line 2, column 29, field 'workpiece.stock_m': '1e400'"},
        {"run " + (dir / "gain_scene.json").string() + " --display offscreen --frames 1 --out " + (dir / "o").string(),
         "gain_scene.json: field 'workspace.scale': must be in [0.01, 100], got"},
    };
    for (const auto& [args, expect] : cases) {
        const RunResult r = run_tridex(args, dir / "run");
        EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
        EXPECT_NE(r.err.find(expect), std::string::npos) << args << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
        EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    }
}

TEST(Version, PrintsTheVersionAndExitsZero) {
    const fs::path out = fs::path(testing::TempDir()) / "tridex_version";
    const RunResult r = run_tridex("--version", out);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    std::ifstream f(out / "stdout.txt");
    std::stringstream text;
    text << f.rdbuf();
    EXPECT_EQ(text.str().rfind("tridex ", 0), 0u) << text.str();
}

// The command table: `tridex --help` lists every command, and each answers its own --help.
TEST(Commands, HelpListsEveryCommandAndEachAnswersItsOwnHelp) {
    const fs::path out = fs::path(testing::TempDir()) / "tridex_help";
    const auto stdout_of = [](const fs::path& dir) {
        std::ifstream f(dir / "stdout.txt");
        std::stringstream text;
        text << f.rdbuf();
        return text.str();
    };
    const RunResult r = run_tridex("--help", out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string help = stdout_of(out);
    for (const char* cmd : {"demo", "run", "replay", "recover", "export", "devices", "device-server", "study", "bench"}) {
        EXPECT_NE(help.find(std::string("\n  ") + cmd + " "), std::string::npos) << cmd << " missing from:\n" << help;
        const fs::path dir = out / cmd;
        const RunResult c = run_tridex(std::string(cmd) + " --help", dir);
        EXPECT_EQ(c.exit_code, 0) << cmd << ": " << c.err;
        EXPECT_NE(stdout_of(dir).find("Usage:"), std::string::npos) << cmd;
    }
}

TEST(Devices, ListsDriversAsTextAndJson) {
    const fs::path out = fs::path(testing::TempDir()) / "tridex_devices";
    RunResult r = run_tridex("devices", out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream tf(out / "stdout.txt");
    std::stringstream text;
    text << tf.rdbuf();
    EXPECT_NE(text.str().find("simulated"), std::string::npos) << text.str();
    EXPECT_NE(text.str().find("Novint Falcon"), std::string::npos) << text.str();
    EXPECT_NE(text.str().find("pointer"), std::string::npos) << text.str();  // the mouse's input kind
    ::setenv("SPNAV_SOCKET", (out / "no-spacenavd.sock").c_str(), 1);  // no daemon answers there
    r = run_tridex("devices --json", out);
    ::unsetenv("SPNAV_SOCKET");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream jf(out / "stdout.txt");
    const nlohmann::json rows = nlohmann::json::parse(jf);
    ASSERT_TRUE(rows.is_array());
    ASSERT_GE(rows.size(), 4u);
    bool wand = false;
    for (const auto& row : rows) {
        ASSERT_TRUE(row.contains("name") && row.contains("dof") && row.contains("detected")) << row.dump();
        EXPECT_TRUE(row["dof"].is_number_integer());
        EXPECT_TRUE(row["detected"].is_boolean());
        // Every driver describes itself: its input kind and what it can do.
        ASSERT_TRUE(row.contains("capabilities")) << row.dump();
        const nlohmann::json& caps = row["capabilities"];
        EXPECT_TRUE(caps["input"].is_string() && caps["renders_forces"].is_boolean() && caps["servable"].is_boolean())
            << row.dump();
        if (row["driver"] == "mouse") {
            EXPECT_EQ(caps["input"], "pointer");
        }
        if (row["driver"] == "spacemouse") {
            EXPECT_EQ(caps["options"].size(), 4u);
            // Detected means found now: no spacenavd answers, so it is not, and the row says why.
            EXPECT_FALSE(row["detected"].get<bool>()) << row.dump();
            EXPECT_NE(row.value("not_detected", "").find("no spacenavd at"), std::string::npos) << row.dump();
        }
        // One source of truth: the row's DOF are its capabilities' DOF; a driver without force outputs none.
        EXPECT_EQ(row["dof_in"], caps["dof_in"]) << row.dump();
        EXPECT_EQ(row["dof_out"], caps["dof_out"]) << row.dump();
        if (!caps["renders_forces"].get<bool>()) {
            EXPECT_EQ(row["dof_out"], 0) << row.dump();
            if (!row["hardware"].get<bool>() && row["profile"] != "-") {
                EXPECT_NE(row["name"].get<std::string>().find(row["driver"].get<std::string>() + " ("), std::string::npos)
                    << row.dump();
            }
        }
        if (row["driver"] == "simulated" && row["profile"] == "wand") {
            wand = true;
            EXPECT_EQ(row["dof"].get<int>(), 5);
            EXPECT_TRUE(row["detected"].get<bool>());
        }
        if (row["driver"] == "falcon") {
            EXPECT_FALSE(row["available"].get<bool>());
        }
    }
    EXPECT_TRUE(wand);
}

// A file of the shared test data (TRIDEX_SHARED_DATA, which ctest sets).
std::string data(const char* rel) { return std::string(TRIDEX_SHARED_DATA_DIR) + "/" + rel; }

// A command that fails leaves no empty output folder behind; a folder that was there already stays.
TEST(Demo, AFailedCommandLeavesNoEmptyOutputFolder) {
    const fs::path dir = fs::temp_directory_path() / ("tridex-test-failed-out-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    auto r = run_tridex("run --display offscreen --frames 1 --device nosuch --out " + (dir / "new" / "deeper").string(),
                        dir / "log1");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_FALSE(fs::exists(dir / "new")) << "the failed run left " << (dir / "new");
    r = run_tridex("demo --resolution 7 --out " + (dir / "demo_out").string(), dir / "log2");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_FALSE(fs::exists(dir / "demo_out"));
    fs::create_directories(dir / "kept");
    r = run_tridex("run --display offscreen --frames 1 --device nosuch --out " + (dir / "kept").string(), dir / "log3");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(fs::exists(dir / "kept"));
    fs::remove_all(dir);
}

TEST(Demo, ShortStrokeWritesConsistentOutputs) {
    const fs::path out = fs::temp_directory_path() / "tridex-test-demo";
    fs::remove_all(out);
    const RunResult r = run_tridex("demo --resolution 96 --seconds 2 --width 320 --height 240 --validate --gpu-contour --out " + out.string(), out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const char* f : {"left.png", "right.png", "sbs.png", "sculpted.ply", "haptics.csv", "report.json"})
        EXPECT_TRUE(fs::exists(out / f)) << f;

    std::ifstream rf(out / "report.json");
    const nlohmann::json j = nlohmann::json::parse(rf);
    const int ticks = j["ticks"];
    // The scripted stylus: the proxy stays with the hand.
    std::printf("[scripted stylus] proxy %s\n", j["haptics"]["proxy"].dump().c_str());
    EXPECT_EQ(j["haptics"]["proxy"]["ticks_over_radius_hip_outside"].get<long>(), 0);
    EXPECT_GT(ticks, 1000);  // 2 s at 1 kHz; a loaded machine skips missed deadlines (the median period is the rate)
    EXPECT_LT(ticks, 2600);
    EXPECT_GT(j["period_us"]["median"].get<double>(), 900.0);
    EXPECT_LT(j["period_us"]["median"].get<double>(), 1100.0);
    EXPECT_GT(j["booleans"].get<int>(), 100);
    EXPECT_GT(j["tiles_recontoured"].get<int>(), 0);
    const double vmesh = j["workpiece"]["volume_mesh_m3"], vdex = j["workpiece"]["volume_dexel_m3"];
    EXPECT_NEAR(vdex / vmesh, 1.0, 0.02);  // 96 cells over the bunny
    EXPECT_GT(j["volume_removed_m3"].get<double>(), 1e-7);  // a groove was carved
    EXPECT_LT(j["volume_removed_m3"].get<double>(), 0.1 * vdex);
    EXPECT_EQ(j["mesh"]["boundary_edges"].get<int>(), 0);
    EXPECT_EQ(j["mesh"]["nonmanifold_edges"].get<int>(), 0);
    EXPECT_GT(j["mesh"]["triangles"].get<int>(), 1000);
    EXPECT_GT(j["haptics"]["contact_ticks"].get<int>(), 100);  // the tool pressed into the bunny
    EXPECT_LE(j["haptics"]["max_force_n"].get<double>(), j["haptics"]["device_max_force_n"].get<double>() + 1e-9);
    // The device went through its lifecycle: closed at the end, no faults, no force cut by the device seam.
    const auto& ds = j["haptics"]["device_status"];
    EXPECT_EQ(ds["state"], "closed");
    EXPECT_EQ(ds["faults"], "none");
    EXPECT_EQ(ds["writes_clamped"].get<int>(), 0);
    EXPECT_GT(ds["writes"].get<int>(), 1000);
    EXPECT_EQ(j["render"]["validation_messages"].get<int>(), 0);
    // Sculpted on the GPU (lavapipe here: --gpu-contour asks for the model there), with the model's memory per ray set.
    EXPECT_EQ(j["sculpt_path"], "gpu");
    EXPECT_EQ(j["sculpt"]["backend"], "gpu");
    EXPECT_NE(j["sculpt"]["backend_reason"].get<std::string>().find("--gpu-contour"), std::string::npos)
        << j["sculpt"]["backend_reason"];
    EXPECT_EQ(j["sculpt_validation_messages"].get<int>(), 0);  // validation is on in tests
    EXPECT_NE(j["device"].get<std::string>().find("llvmpipe"), std::string::npos) << j["device"];
    EXPECT_GE(j["spilled_intervals"].get<long>(), 0);
    EXPECT_GT(j["model_bytes"]["total"].get<double>(), 3.0 * 97 * 97 * 24);  // 24 B per ray at least
    // Contoured on the GPU too (--gpu-contour: the images drawn from its buffers), nothing handed to the host.
    EXPECT_EQ(j["contour_path"], "gpu");
    EXPECT_GT(j["contour"]["gpu"]["tiles_gpu"].get<long>(), 0);
    EXPECT_EQ(j["contour"]["gpu"]["host_fallback_tiles"].get<long>(), 0);

    // haptics.csv: a header and one row per tick.
    std::ifstream csv(out / "haptics.csv");
    std::string line;
    int rows = -1;
    while (std::getline(csv, line)) ++rows;
    EXPECT_EQ(rows, ticks);

    // The two eyes see different views of the same scene.
    int w[2], h[2], c[2];
    unsigned char* img[2] = {stbi_load((out / "left.png").c_str(), &w[0], &h[0], &c[0], 4),
                             stbi_load((out / "right.png").c_str(), &w[1], &h[1], &c[1], 4)};
    ASSERT_TRUE(img[0] && img[1]);
    ASSERT_EQ(w[0], 320);
    ASSERT_EQ(h[0], 240);
    std::size_t differ = 0;
    for (int i = 0; i < 320 * 240; ++i)
        for (int k = 0; k < 3; ++k)
            if (std::abs(img[0][4 * i + k] - img[1][4 * i + k]) > 8) { ++differ; break; }
    EXPECT_GT(differ, 200u);
    stbi_image_free(img[0]);
    stbi_image_free(img[1]);
}

// On a CPU implementation of Vulkan (lavapipe here) the default sculpting backend is the CPU pool and the default
// contour the CPU's, and the report says why; --cpu-contour with --gpu-contour is refused, and so is --cpu with --gpu.
TEST(Demo, LavapipeContoursOnTheCpuByDefault) {
    const fs::path out = fs::temp_directory_path() / "tridex-test-demo-cpu-contour";
    fs::remove_all(out);
    const RunResult bad = run_tridex("demo --cpu-contour --gpu-contour --out " + out.string(), out);
    EXPECT_NE(bad.exit_code, 0);
    EXPECT_NE(bad.err.find("excludes"), std::string::npos) << bad.err;
    const RunResult both = run_tridex("demo --cpu --gpu --out " + out.string(), out);
    EXPECT_EQ(both.exit_code, 2);
    EXPECT_NE(both.err.find("excludes"), std::string::npos) << both.err;
    const RunResult r = run_tridex("demo --resolution 64 --seconds 1 --width 160 --height 120 --validate --out " +
                                       out.string(), out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream rf(out / "report.json");
    const nlohmann::json j = nlohmann::json::parse(rf);
    EXPECT_EQ(j["sculpt_path"], "cpu");
    EXPECT_EQ(j["sculpt"]["backend"], "cpu");
    EXPECT_NE(j["sculpt"]["backend_reason"].get<std::string>().find("auto: the Vulkan device is a CPU implementation (llvmpipe"),
              std::string::npos) << j["sculpt"]["backend_reason"];
    EXPECT_EQ(j["sculpt_path_reason"], j["sculpt"]["backend_reason"]);
    EXPECT_EQ(j["contour_path"], "cpu");
    EXPECT_NE(j["contour_path_reason"].get<std::string>().find("CPU implementation"), std::string::npos)
        << j["contour_path_reason"];
    EXPECT_EQ(j["contour"]["gpu"]["tiles"].get<long>(), 0);
    EXPECT_EQ(j["render"]["validation_messages"].get<int>(), 0);
    EXPECT_EQ(j["mesh"]["boundary_edges"].get<int>(), 0);
    fs::remove_all(out);
}

// --keep-islands on the command line of demo and run: stored in the settings (so replay and recover follow it), no
// stroke searched; without it the strokes that cut are searched and the carved mesh is one part.
TEST(Demo, KeepIslandsIsASessionSettingOfDemoAndRun) {
    const fs::path dir = fs::temp_directory_path() / ("tridex-test-keep-islands-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    const std::string demo = "demo --resolution 48 --seconds 1 --width 64 --height 48 --cpu --no-journal --out ";
    ASSERT_EQ(run_tridex(demo + (dir / "remove").string(), dir / "remove").exit_code, 0);
    ASSERT_EQ(run_tridex(demo + (dir / "keep").string() + " --keep-islands", dir / "keep").exit_code, 0);
    const nlohmann::json removed = tridex::app::test::read_json(dir / "remove" / "report.json");
    const nlohmann::json kept = tridex::app::test::read_json(dir / "keep" / "report.json");
    EXPECT_EQ(removed["settings"]["keep_islands"], false);
    EXPECT_GE(removed["sculpt"]["island_searches"].get<int>(), 1);
    EXPECT_EQ(removed["mesh"]["components"], 1);
    EXPECT_EQ(kept["settings"]["keep_islands"], true);
    EXPECT_EQ(kept["sculpt"]["island_searches"], 0);
    EXPECT_EQ(kept["sculpt"]["islands_removed"], 0);
    const std::string scene = (dir / "scene.json").string();
    std::ofstream(scene) << R"({
  "workpiece": { "resolution": 48, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "stroke": { "duration_s": 0.5, "length_m": 0.04, "depth_m": 0.003, "press_axis": "z" },
  "display": { "preset": "desktop", "resolution": [64, 48], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.05, 0.6] }
})";
    const RunResult run = run_tridex("run " + scene + " --display offscreen --stereo mono --cpu --no-journal --keep-islands --out " +
                                         (dir / "run").string(), dir / "run");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const nlohmann::json r = tridex::app::test::read_json(dir / "run" / "report.json");
    EXPECT_EQ(r["settings"]["keep_islands"], true);
    EXPECT_EQ(r["sculpt"]["island_searches"], 0);
    if (!HasFailure()) fs::remove_all(dir);
}

// The Falcon driver end to end over its emulator: firmware load, homing, the 1 kHz exchange, a carved groove.
TEST(Demo, FalconEmulatorRunsTheDemo) {
    const fs::path out = fs::temp_directory_path() / "tridex-test-demo-falcon";
    fs::remove_all(out);
    const RunResult r = run_tridex(
        "demo --device falcon-emulator --resolution 64 --seconds 1.5 --width 160 --height 120 "
        "--validate --out " +
            out.string(),
        out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream rf(out / "report.json");
    const nlohmann::json j = nlohmann::json::parse(rf);
    const nlohmann::json& h = j["haptics"];
    EXPECT_EQ(h["device"], "Novint Falcon");
    EXPECT_EQ(h["device_driver"], "falcon-emulator");
    EXPECT_EQ(h["device_status"]["faults"], "none");
    EXPECT_GT(h["contact_ticks"].get<long>(), 0);
    EXPECT_GT(h["device_link"]["homed_at_s"].get<double>(), 0.0);
    EXPECT_EQ(h["device_link"]["missed_frames"].get<long>(), 0);
    // The proxy stays with the hand at 1 kHz on the emulated Falcon's scripted grip.
    std::printf("[falcon emulator] proxy %s\n", h["proxy"].dump().c_str());
    EXPECT_EQ(h["proxy"]["ticks_over_radius_hip_outside"].get<long>(), 0);
    EXPECT_GT(j["volume_removed_m3"].get<double>(), 0.0);
    EXPECT_EQ(j["render"]["validation_messages"].get<int>(), 0);
    // Without a Falcon plugged in, --device falcon says so in one line.
    const RunResult none = run_tridex("demo --device falcon --out " + out.string(), out);
    if (none.exit_code != 0) {  // (a machine with a Falcon plugged in runs the demo on it instead)
        EXPECT_EQ(none.exit_code, 2) << none.err;
        EXPECT_NE(none.err.find("Novint Falcon"), std::string::npos) << none.err;
    }
    fs::remove_all(out);
}

std::string file_bytes(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

TEST(Replay, ARecordedSessionSculptsTheSameModel) {
    const fs::path dir = fs::temp_directory_path() / ("tridex-test-replay-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    const fs::path rec = dir / "session.trdx";
    // A wand (a flat-end mill with two points at its ends) on the 5-DOF profile, so torques and both points are recorded.
    const RunResult live = run_tridex("demo --resolution 64 --seconds 1.5 --width 96 --height 72 --tool flat_end "
                                      "--tool-length-mm 20 --points 2 --device wand --gpu "
                                      "--record " + rec.string() + " --out " + (dir / "live").string(), dir / "live");
    ASSERT_EQ(live.exit_code, 0) << live.err;
    ASSERT_TRUE(fs::exists(rec));
    const RunResult again = run_tridex("replay " + rec.string() + " --width 96 --height 72 --out " + (dir / "replay").string(),
                                       dir / "replay");
    ASSERT_EQ(again.exit_code, 0) << again.err;
    // The same tool-sample stream gives the same dexels, so the same contoured mesh, byte for byte.
    const std::string a = file_bytes(dir / "live" / "sculpted.ply"), b = file_bytes(dir / "replay" / "sculpted.ply");
    ASSERT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == b) << "replayed mesh differs from the live one";
    std::ifstream ra(dir / "live" / "report.json"), rb(dir / "replay" / "report.json");
    const nlohmann::json ja = nlohmann::json::parse(ra), jb = nlohmann::json::parse(rb);
    EXPECT_EQ(ja["volume_removed_m3"], jb["volume_removed_m3"]);
    EXPECT_GT(ja["volume_removed_m3"].get<double>(), 0.0);
    EXPECT_EQ(ja["ticks"], jb["ticks"]);
    EXPECT_EQ(jb["haptics"]["points"], 2);
    EXPECT_EQ(jb["haptics"]["device"], "Quanser 5-DOF Haptic Wand");
    // The live session sculpted on the GPU; replayed on the CPU reference it gives the same mesh.
    EXPECT_EQ(ja["sculpt_path"], "gpu");
    const RunResult cpu = run_tridex("replay " + rec.string() + " --cpu --width 96 --height 72 --out " + (dir / "cpu").string(),
                                     dir / "cpu");
    ASSERT_EQ(cpu.exit_code, 0) << cpu.err;
    std::ifstream rc(dir / "cpu" / "report.json");
    const nlohmann::json jc = nlohmann::json::parse(rc);
    EXPECT_EQ(jc["sculpt_path"], "cpu");
    EXPECT_EQ(jc["sculpt_path_reason"], "--cpu given");
    EXPECT_EQ(jc["spilled_intervals"], 0);
    EXPECT_TRUE(file_bytes(dir / "cpu" / "sculpted.ply") == a) << "the CPU path sculpted a different model";

    // A damaged recording is refused with one line naming the file.
    std::string bytes = file_bytes(rec);
    bytes.resize(bytes.size() - 100);
    const fs::path bad = dir / "cut.trdx";
    std::ofstream(bad, std::ios::binary) << bytes;
    const RunResult refused = run_tridex("replay " + bad.string() + " --out " + (dir / "bad").string(), dir / "bad");
    EXPECT_EQ(refused.exit_code, 2) << refused.err;
    EXPECT_NE(refused.err.find("cut.trdx"), std::string::npos) << refused.err;
    EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << refused.err;
}

class BadMesh : public testing::TestWithParam<const char*> {};

TEST_P(BadMesh, IsRefusedWithOneClearLine) {
    const std::string file = data(GetParam());
    // One folder per case: ctest runs the cases in parallel and each captures its own stderr.
    const fs::path out = fs::temp_directory_path() / ("tridex-test-bad-" + fs::path(file).filename().string());
    const RunResult r = run_tridex("demo --resolution 32 --seconds 1 --out " + out.string() + " --mesh " + file, out);
    EXPECT_EQ(r.exit_code, 2) << r.err;  // tridex::Error, not a crash (>= 128) or timeout (124)
    EXPECT_NE(r.err.find(fs::path(file).filename().string()), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

INSTANTIATE_TEST_SUITE_P(SharedBadData, BadMesh,
                         testing::Values("bad/OutOfMemory.off", "bad/empty.obj", "bad/empty.off", "bad/empty.ply",
                                         "bad/malformed.obj", "bad/malformed2.obj", "meshes/elephant-with-holes.off"));

// Malformed meshes that once crashed, hung or exhausted memory in the reader: each is refused in one printable line
// that names the file and the line.
TEST(MalformedMesh, IsRefusedNotCrashedOn) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-malformed-meshes";
    fs::create_directories(dir);
    const std::string tet = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    const std::string props = "property float x\nproperty float y\nproperty float z\n";
    const std::pair<std::string, std::string> cases[] = {
        {"order.ply", "ply\nformat ascii 1.0\nproperty float x\nelement vertex 4\nproperty float y\nproperty float z\n"
                      "element face 4\nproperty list uchar int vertex_indices\nend_header\n" + tet},
        {"format.ply", "ply\nformat binary_little_endian\nelement vertex 4\n" + props +
                           "element face 4\nproperty list uchar int vertex_indices\nend_header\n" + tet},
        {"absurd.ply", "ply\nformat ascii 1.0\nelement vertex 4\n" + props +
                           "element face 4\nproperty list uint int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                           "3000000000 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
        {"absurd.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3000000000 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
        {"escape.ply", "ply\nformat ascii 1.0\nelement vertex 4\n" + props +
                           "element face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 \x1b[31m0\n0 0 1\n"
                           "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
    };
    for (const auto& [name, text] : cases) {
        SCOPED_TRACE(name);
        const fs::path file = dir / name;
        std::ofstream(file, std::ios::binary) << text;
        const fs::path out = dir / ("out-" + name);
        const RunResult r = run_tridex("demo --resolution 32 --seconds 1 --out " + out.string() + " --mesh " + file.string(), out);
        EXPECT_EQ(r.exit_code, 2) << r.err;
        EXPECT_EQ(r.err.rfind("tridex: " + file.string() + ":", 0), 0u) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        for (const char c : r.err) EXPECT_TRUE(c == '\n' || (c >= 0x20 && c < 0x7f)) << r.err;
    }
}

// An output that cannot be written (here left.png, a folder in the way) is said at once and costs no other: the
// report (which notes it), the recording and the model are still written, and the exit status says it.
TEST(Outputs, AFailedOutputCostsNoOther) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_failed_output";
    fs::remove_all(dir);
    fs::create_directories(dir / "out" / "left.png" / "in_the_way");
    const RunResult r = run_tridex("demo --resolution 32 --seconds 1 --out " + (dir / "out").string() + " --save " +
                                       (dir / "m.tdx").string() + " --record " + (dir / "r.trdx").string(),
                                   dir / "log");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("left.png"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("1 of 8 outputs were not written"), std::string::npos) << r.err;
    for (const char* f : {"out/right.png", "out/sbs.png", "out/sculpted.ply", "out/haptics.csv", "out/report.json", "m.tdx", "r.trdx"})
        EXPECT_TRUE(fs::is_regular_file(dir / f)) << f;
    std::ifstream rf(dir / "out" / "report.json");
    const nlohmann::json rep = nlohmann::json::parse(rf);
    bool noted = false;
    for (const auto& n : rep["notes"]) noted = noted || n.get<std::string>().rfind("not written: ", 0) == 0;
    EXPECT_TRUE(noted) << rep["notes"];
    for (const auto& f : rep["files"]) EXPECT_EQ(f.get<std::string>().find("left.png"), std::string::npos) << f;
}

}  // namespace
