// `tridex device-server` and `tridex demo --device net:HOST:PORT` as two processes over ENet on loopback, as a user
// runs them on two machines: the session carves in both rendering modes and reports the link. The server is a
// child process on a port the kernel picks; the test waits for its "serving" line (never a fixed sleep) and always
// kills it.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "../test_paths.hpp"
#include "child_process.hpp"
#include "test_files.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using tridex::app::test::Child;
using tridex::app::test::read_json;
using tridex::app::test::run_tridex;

class NetSession : public ::testing::TestWithParam<const char*> {};

TEST_P(NetSession, DemoAgainstADeviceServerProcessCarvesAndReportsTheLink) {
    const std::string mode = GetParam();
    const fs::path dir = fs::path(testing::TempDir()) / ("tridex_net_session_" + mode);
    fs::remove_all(dir);
    fs::create_directories(dir);
    // Port 0: the kernel picks a free one, which the server prints. --once: the server ends with the session, so a
    // session whose connection the server timed out while it loaded (a 512-cell workpiece takes seconds) gets nothing.
    Child server({TRIDEX_EXE, "device-server", "--device", "simulated", "--listen", "127.0.0.1:0", "--stroke-seconds",
                  "2", "--once", "--seconds", "240"});
    ASSERT_TRUE(server.started());
    std::string port;
    ASSERT_TRUE(server.wait_for_line(std::regex(R"(on 127\.0\.0\.1:([0-9]+);)"), 120.0, port)) << server.seen();

    const auto r = run_tridex("demo --device net:127.0.0.1:" + port + " --haptic-rendering " + mode +
                                  " --seconds 2 --resolution 512 --width 64 --height 48 --no-journal --out " + (dir / "out").string(),
                              dir / "run");
    ASSERT_EQ(r.exit_code, 0) << r.err << "\nserver:\n" << server.seen();
    const nlohmann::json rep = read_json(dir / "out" / "report.json");
    // The workpiece was carved: the stroke removed material.
    const double before = rep["workpiece"]["volume_dexel_m3"].get<double>();
    EXPECT_GT(rep["volume_removed_m3"].get<double>(), 1e-3 * before) << "no material removed in " << mode << " mode";
    const nlohmann::json& link = rep["link"];
    ASSERT_TRUE(link.is_object()) << rep.dump(1);
    EXPECT_EQ(link["mode"], mode);
    EXPECT_FALSE(link["sealed"].get<bool>()) << "no key was given: " << link.dump();
    // States at (close to) the server's 1 kHz; a loaded machine may thin them, never to nothing.
    EXPECT_GT(link["rate_hz"].get<double>(), 200.0) << link.dump();
    EXPECT_GT(link["rtt_us"]["median"].get<double>(), 0.0) << link.dump();
    EXPECT_GE(link["rtt_us"]["p99"].get<double>(), link["rtt_us"]["median"].get<double>());
    EXPECT_GT(rep["haptics"]["device_link"]["exchanges"].get<long>(), 1000) << rep["haptics"].dump(1);
    // The connection outlived the session's set-up: never dropped and welcomed again.
    EXPECT_EQ(link["events"].get<std::string>().find("disconnected"), std::string::npos) << link.dump();
    // The session's end ends the --once server, which says how many sessions it served.
    std::string sessions;
    EXPECT_TRUE(server.wait_for_line(std::regex(R"(device-server: ([0-9]+) sessions)"), 60.0, sessions)) << server.seen();
    EXPECT_GE(sessions, "1");
}

// `tridex run` with a served device: the scene's stroke is carved with the server's hand, the link reported.
TEST(NetRun, OffscreenRunAgainstADeviceServerProcessInLocalRendering) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_net_run";
    fs::remove_all(dir);
    fs::create_directories(dir);
    Child server({TRIDEX_EXE, "device-server", "--device", "simulated", "--listen", "127.0.0.1:0", "--stroke-seconds",
                  "3", "--once", "--seconds", "240"});
    ASSERT_TRUE(server.started());
    std::string port;
    ASSERT_TRUE(server.wait_for_line(std::regex(R"(on 127\.0\.0\.1:([0-9]+);)"), 120.0, port)) << server.seen();
    const auto r = run_tridex("run --display offscreen --device net:127.0.0.1:" + port +
                                  " --haptic-rendering local --no-journal --out " + (dir / "out").string(),
                              dir / "run");
    ASSERT_EQ(r.exit_code, 0) << r.err << "\nserver:\n" << server.seen();
    const nlohmann::json rep = read_json(dir / "out" / "report.json");
    EXPECT_GT(rep["volume_before_m3"].get<double>() - rep["volume_after_m3"].get<double>(), 0.0) << "nothing carved";
    const nlohmann::json& link = rep["link"];  // where the demo's report has it
    ASSERT_TRUE(link.is_object()) << rep.dump(1);
    EXPECT_EQ(link, rep["haptics"]["link"]);
    EXPECT_EQ(link["mode"], "local");
    EXPECT_GT(link["rate_hz"].get<double>(), 200.0) << link.dump();
    EXPECT_GT(link["rtt_us"]["median"].get<double>(), 0.0) << link.dump();
    // Ticks that had only an earlier tool sample are reported as stale, and are the exception.
    ASSERT_TRUE(link["stale_tool_samples"].is_number_unsigned()) << link.dump();
    EXPECT_LT(link["stale_tool_samples"].get<double>(), 0.5 * rep["haptics"]["ticks"].get<double>()) << link.dump();
    std::printf("[net run] local rendering: %s of %s ticks with a stale tool sample\n",
                link["stale_tool_samples"].dump().c_str(), rep["haptics"]["ticks"].dump().c_str());
}

// A device that goes away mid-session (here its device server stops) ends the session: its outputs are written, one
// line on stderr names the device, when it was lost and what was kept, and the command exits 4.
TEST(DeviceLost, AServerThatStopsEndsDemoAndRunWithExit4AndKeepsTheirWork) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_device_lost";
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const std::string command : {"demo", "run"}) {
        Child server({TRIDEX_EXE, "device-server", "--device", "simulated", "--listen", "127.0.0.1:0", "--stroke-seconds",
                      "60", "--seconds", "6"});
        ASSERT_TRUE(server.started());
        std::string port;
        ASSERT_TRUE(server.wait_for_line(std::regex(R"(on 127\.0\.0\.1:([0-9]+);)"), 120.0, port)) << server.seen();
        const fs::path out = dir / command;
        const std::string args =
            command == "demo" ? "demo --seconds 60 --resolution 48 --width 64 --height 48 --save " + (dir / "demo.tdx").string()
                              : "run --display offscreen --seconds 60 --save " + (dir / "run.tdx").string();
        const auto t0 = Clock::now();
        const auto r = run_tridex(args + " --device net:127.0.0.1:" + port + " --out " + out.string(), dir / (command + "_log"));
        const double took_s = std::chrono::duration<double>(Clock::now() - t0).count();
        EXPECT_EQ(r.exit_code, 4) << command << ": " << r.err << "\nserver:\n" << server.seen();
        EXPECT_LT(took_s, 45.0) << command << ": the session went on long after its device was gone";
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_TRUE(std::regex_search(r.err, std::regex("was lost [0-9.]+ s into the session"))) << "says when: " << r.err;
        EXPECT_NE(r.err.find("net"), std::string::npos) << "names the device: " << r.err;
        EXPECT_NE(r.err.find(out.string()), std::string::npos) << "says what was kept: " << r.err;
        for (const char* f : {"sculpted.ply", "report.json", "session.tdj"})
            EXPECT_TRUE(fs::is_regular_file(out / f)) << command << ": " << f;
        EXPECT_TRUE(fs::is_regular_file(dir / (command + ".tdx"))) << command << ": --save was not written";
        const nlohmann::json rep = read_json(out / "report.json");
        EXPECT_EQ(rep["notes"][0].get<std::string>().rfind("ended: the device was lost at", 0), 0u) << rep["notes"];
        EXPECT_TRUE(rep["haptics"]["device_lost"].get<bool>());
    }
    fs::remove_all(dir);
}

// What `run` refuses about served devices, in one line naming the flag or field.
TEST(NetRun, BadNetOptionsAreRefusedWithOneLine) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_net_run_bad";
    fs::create_directories(dir);
    const fs::path scene = dir / "scene.json";
    std::ofstream(scene) << R"({"device": {"driver": "net", "address": "nowhere"}})";
    const std::pair<std::string, std::string> cases[] = {
        {"run --display offscreen --haptic-rendering local --frames 1", "--haptic-rendering local: only with --device net"},
        {"run --display offscreen --device net:127.0.0.1:99999 --frames 1", "is not HOST:PORT"},
        {"run --display offscreen --device net:127.0.0.1:7 --haptic-rendering both --frames 1", "'both' is not distributed or local"},
        {"run " + scene.string() + " --display offscreen --frames 1", "field 'device.address'"},
    };
    for (const auto& [args, expect] : cases) {
        const auto r = run_tridex(args, dir / "run");
        EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
        EXPECT_NE(r.err.find(expect), std::string::npos) << args << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
    }
}

INSTANTIATE_TEST_SUITE_P(BothModes, NetSession, ::testing::Values("distributed", "local"),
                         [](const ::testing::TestParamInfo<const char*>& i) { return std::string(i.param); });

}  // namespace
