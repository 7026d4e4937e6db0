// A device server killed (SIGKILL) mid-stroke, in both haptic-rendering modes: the session runs to its end with the
// force at zero, then ends with exit 4 and one line naming the device, when it was lost and the files it kept; those
// files are written (report.json says the device was lost).
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <regex>
#include <string>
#include <thread>

#include "../test_paths.hpp"
#include "child_process.hpp"
#include "test_files.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

class ChaosDeviceServer : public ::testing::TestWithParam<const char*> {};

TEST_P(ChaosDeviceServer, KilledMidStrokeEndsTheSessionWithExit4AndKeepsItsWork) {
    const std::string mode = GetParam();
    const fs::path dir = fs::path(testing::TempDir()) / ("tridex_chaos_server_" + mode);
    fs::remove_all(dir);
    test::Child server({TRIDEX_EXE, "device-server", "--device", "simulated", "--listen", "127.0.0.1:0",
                        "--stroke-seconds", "4", "--seconds", "240"});
    ASSERT_TRUE(server.started());
    std::string port;
    ASSERT_TRUE(server.wait_for_line(std::regex(R"(on 127\.0\.0\.1:([0-9]+);)"), 120.0, port)) << server.seen();
    test::Child session({TRIDEX_EXE, "demo", "--device", "net:127.0.0.1:" + port, "--haptic-rendering", mode,
                         "--seconds", "4", "--resolution", "48", "--width", "32", "--height", "32", "--out",
                         (dir / "out").string()},
                        true);
    ASSERT_TRUE(session.started());
    // Mid-stroke: once the session's journal is there, a second and a half into the stroke.
    const fs::path journal = dir / "out" / "session.tdj";
    for (int i = 0; i < 12000 && !fs::exists(journal); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ASSERT_TRUE(fs::exists(journal)) << session.seen();
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    ::kill(server.pid(), SIGKILL);
    const int code = session.finish();
    const std::string& said = session.seen();
    EXPECT_EQ(code, 4) << said;
    const std::regex lost("tridex: --device net:127\\.0\\.0\\.1:" + port + ": the .* was lost [0-9.]+ s into the session; "
                          "the session ended there and kept its work: .*report\\.json.*the journal");
    EXPECT_TRUE(std::regex_search(said, lost)) << said;
    const nlohmann::json rep = test::read_json(dir / "out" / "report.json");
    EXPECT_NE(rep["notes"][0].get<std::string>().find("the device was lost at"), std::string::npos) << rep["notes"];
    for (const char* f : {"sculpted.ply", "left.png", "report.json"}) EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
}

INSTANTIATE_TEST_SUITE_P(Modes, ChaosDeviceServer, ::testing::Values("distributed", "local"));

}  // namespace
}  // namespace tridex::app
