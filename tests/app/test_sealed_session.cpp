// `tridex device-server --key-file/--passphrase-env` and `tridex demo --device net:...` with and without the same
// key, as two processes over ENet on loopback: the same key carves as an unsealed link does; another key, or a
// sealed server facing an unsealed session (and the other way round), ends the session within seconds with one line
// naming the server's address, exit code 2 (as an unreachable server), and the server counts what it refused.
#include <gtest/gtest.h>

#include <signal.h>
#include <stdlib.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "../test_paths.hpp"
#include "child_process.hpp"
#include "test_files.hpp"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using tridex::app::test::Child;
using tridex::app::test::read_json;
using tridex::app::test::run_tridex;

fs::path test_dir(const std::string& name) { return tridex::app::test::fresh_test_dir("tridex_sealed_", name); }

fs::path key_file(const fs::path& dir, const std::string& name, const char* b) {
    return tridex::app::test::hex_key_file(dir, name, b);
}

// A device server on a free port with these extra arguments; returns its port ("" when it did not start).
std::string start_server(Child& server) {
    std::string port;
    if (!server.started()) return port;
    if (!server.wait_for_line(std::regex(R"(on 127\.0\.0\.1:([0-9]+);)"), 120.0, port)) return "";
    return port;
}

std::vector<std::string> server_args(const std::vector<std::string>& extra) {
    std::vector<std::string> a = {TRIDEX_EXE, "device-server", "--device", "simulated", "--listen", "127.0.0.1:0",
                                  "--stroke-seconds", "2", "--seconds", "120"};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
}

// Stops the server as Ctrl+C does and returns its closing line ("" when there was none).
std::string closing_line(Child& server) {
    kill(server.pid(), SIGINT);
    server.finish();
    std::smatch m;
    const std::string seen = server.seen();
    return std::regex_search(seen, m, std::regex(R"(device-server: [0-9]+ sessions[^\n]*)")) ? m.str() : "";
}

// A session against `port` with these key arguments, which must fail: its one line and how long it took.
struct Refusal {
    int exit_code = 0;
    std::string err;
    double took_s = 0.0;
};

Refusal refused_demo(const std::string& port, const std::string& key_args, const fs::path& dir) {
    const auto t0 = Clock::now();
    const auto r = run_tridex("demo --device net:127.0.0.1:" + port + " " + key_args +
                                  " --seconds 2 --resolution 48 --width 64 --height 48 --no-journal --out " +
                                  (dir / "out").string(),
                              dir / "run");
    return {r.exit_code, r.err, std::chrono::duration<double>(Clock::now() - t0).count()};
}

TEST(SealedNetSession, TheSameKeyOnBothSidesCarvesAndReportsTheLink) {
    const fs::path dir = test_dir("same_key");
    ASSERT_EQ(setenv("TRIDEX_TEST_SEAL_PASSPHRASE", "correct horse battery staple", 1), 0);
    Child server(server_args({"--passphrase-env", "TRIDEX_TEST_SEAL_PASSPHRASE", "--once"}));
    const std::string port = start_server(server);
    ASSERT_FALSE(port.empty()) << server.seen();
    std::string sealed_line;
    EXPECT_TRUE(server.wait_for_line(std::regex("(the link is sealed with the passphrase in .TRIDEX_TEST_SEAL_PASSPHRASE)"),
                                     10.0, sealed_line))
        << server.seen();
    const auto r = run_tridex("demo --device net:127.0.0.1:" + port +
                                  " --passphrase-env TRIDEX_TEST_SEAL_PASSPHRASE --seconds 2 --resolution 256 --width 64 "
                                  "--height 48 --no-journal --out " + (dir / "out").string(),
                              dir / "run");
    ASSERT_EQ(r.exit_code, 0) << r.err << "\nserver:\n" << server.seen();
    const nlohmann::json rep = read_json(dir / "out" / "report.json");
    EXPECT_GT(rep["volume_removed_m3"].get<double>(), 1e-3 * rep["workpiece"]["volume_dexel_m3"].get<double>());
    const nlohmann::json& link = rep["link"];
    ASSERT_TRUE(link.is_object()) << rep.dump(1);
    EXPECT_GT(link["rate_hz"].get<double>(), 200.0) << link.dump();
    EXPECT_GT(link["rtt_us"]["median"].get<double>(), 0.0) << link.dump();
    EXPECT_TRUE(link["sealed"].get<bool>()) << link.dump();
    EXPECT_EQ(link["seal_refused"].get<long>(), 0) << link.dump();
    EXPECT_GT(rep["haptics"]["device_link"]["exchanges"].get<long>(), 1000) << rep["haptics"].dump(1);
    EXPECT_EQ(link["events"].get<std::string>().find("disconnected"), std::string::npos) << link.dump();
    // The --once server ends with the session: its closing line says the sealed link accepted and refused nothing.
    std::string line;
    ASSERT_TRUE(server.wait_for_line(std::regex(R"((device-server: [0-9]+ sessions.*))"), 60.0, line)) << server.seen();
    EXPECT_TRUE(std::regex_search(line, std::regex(R"(sealed link: [1-9][0-9]* accepted, 0 refused)"))) << line;
    std::printf("[sealed] same key: %s\n", line.c_str());
    unsetenv("TRIDEX_TEST_SEAL_PASSPHRASE");
}

TEST(SealedNetSession, AnotherKeyIsRefusedWithinSecondsAndCountedAndTheNextSessionIsServed) {
    const fs::path dir = test_dir("wrong_key");
    Child server(server_args({"--key-file", key_file(dir, "server.key", "5a").string()}));
    const std::string port = start_server(server);
    ASSERT_FALSE(port.empty()) << server.seen();
    const Refusal r = refused_demo(port, "--key-file " + key_file(dir, "session.key", "a5").string(), dir);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("device server at 127.0.0.1:" + port), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("the handshake failed"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("different keys"), std::string::npos) << r.err;
    EXPECT_LT(r.took_s, 10.0) << r.err;
    // The refused session does not hold the server: one with the server's key is served right after it.
    const auto ok = run_tridex("demo --device net:127.0.0.1:" + port + " --key-file " +
                                   key_file(dir, "same.key", "5a").string() +
                                   " --seconds 1 --resolution 48 --width 64 --height 48 --no-journal --out " +
                                   (dir / "ok").string(),
                               dir / "ok_run");
    EXPECT_EQ(ok.exit_code, 0) << ok.err << "\nserver:\n" << server.seen();
    const std::string line = closing_line(server);
    EXPECT_TRUE(std::regex_search(line, std::regex(R"(sealed link: [1-9][0-9]* accepted, [1-9][0-9]* refused \(hello_refused [1-9][0-9]*\))")))
        << server.seen();
    EXPECT_NE(line.find("device-server: 1 sessions"), std::string::npos) << line;
    std::printf("[sealed] another key: %.2f s; %s\n", r.took_s, line.c_str());
}

TEST(SealedNetSession, ASealedServerRefusesAnUnsealedSessionAndTheOtherWayRound) {
    const fs::path dir = test_dir("one_side");
    const fs::path key = key_file(dir, "site.key", "c3");
    {  // the server sealed, the session not
        Child server(server_args({"--key-file", key.string()}));
        const std::string port = start_server(server);
        ASSERT_FALSE(port.empty()) << server.seen();
        const Refusal r = refused_demo(port, "", dir / "unsealed_session");
        EXPECT_EQ(r.exit_code, 2) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_NE(r.err.find("device server at 127.0.0.1:" + port + ": the handshake failed"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("is it sealed?"), std::string::npos) << r.err;
        EXPECT_LT(r.took_s, 10.0) << r.err;
        const std::string line = closing_line(server);
        EXPECT_TRUE(std::regex_search(line, std::regex(R"(sealed link: 0 accepted, [1-9][0-9]* refused)"))) << server.seen();
        std::printf("[sealed] unsealed session: %.2f s; %s\n", r.took_s, line.c_str());
    }
    {  // the session sealed, the server not: it says so at start, and the session gives up after its wait
        Child server(server_args({}));
        const std::string port = start_server(server);
        ASSERT_FALSE(port.empty()) << server.seen();
        std::string unused;
        EXPECT_TRUE(server.wait_for_line(std::regex("the link is not authenticated"), 10.0, unused)) << server.seen();
        const Refusal r = refused_demo(port, "--key-file " + key.string(), dir / "unsealed_server");
        EXPECT_EQ(r.exit_code, 2) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_NE(r.err.find("device server at 127.0.0.1:" + port + " accepted the connection but did not complete"),
                  std::string::npos)
            << r.err;
        EXPECT_LT(r.took_s, 10.0) << r.err;
        const std::string line = closing_line(server);
        EXPECT_NE(line.find("link not authenticated"), std::string::npos) << server.seen();
        std::printf("[sealed] unsealed server: %.2f s; %s\n", r.took_s, line.c_str());
    }
}

// `tridex run` with a scene naming the key file relative to itself (the run starts elsewhere): served, as with the
// same key on both sides.
TEST(SealedNetSession, ASceneNamesItsKeyFileRelativeToItself) {
    const fs::path dir = test_dir("scene");
    const fs::path scene_dir = dir / "scene";
    fs::create_directories(scene_dir);
    Child server(server_args({"--key-file", key_file(scene_dir, "site.key", "7e").string(), "--once"}));
    const std::string port = start_server(server);
    ASSERT_FALSE(port.empty()) << server.seen();
    std::ofstream(scene_dir / "scene.json") << R"({"device": {"driver": "net", "address": "127.0.0.1:)" << port
                                            << R"(", "key_file": "site.key"}})";
    const auto r = run_tridex("run " + (scene_dir / "scene.json").string() + " --display offscreen --no-journal --out " +
                                  (dir / "out").string(),
                              dir / "run");
    ASSERT_EQ(r.exit_code, 0) << r.err << "\nserver:\n" << server.seen();
    const nlohmann::json rep = read_json(dir / "out" / "report.json");
    ASSERT_TRUE(rep["link"].is_object()) << rep.dump(1);
    EXPECT_GT(rep["link"]["rate_hz"].get<double>(), 200.0) << rep["link"].dump();
    std::string line;
    ASSERT_TRUE(server.wait_for_line(std::regex(R"((device-server: [0-9]+ sessions.*))"), 60.0, line)) << server.seen();
    EXPECT_TRUE(std::regex_search(line, std::regex(R"(1 sessions.*sealed link: [1-9][0-9]* accepted, 0 refused)"))) << line;
}

// Bad key settings are refused at once, in one line naming the option, before anything connects.
TEST(SealedNetSession, BadKeySettingsAreRefusedWithOneLine) {
    const fs::path dir = test_dir("bad");
    unsetenv("TRIDEX_TEST_SEAL_UNSET");
    ASSERT_EQ(setenv("TRIDEX_TEST_SEAL_EMPTY", "", 1), 0);
    const fs::path key = key_file(dir, "k.key", "11");
    const fs::path both = dir / "both.json", simulated = dir / "simulated.json";
    std::ofstream(both) << R"({"device": {"driver": "net", "address": "127.0.0.1:9", "key_file": "k.key", )"
                        << R"("passphrase_env": "TRIDEX_TEST_SEAL_EMPTY"}})";
    std::ofstream(simulated) << R"({"device": {"driver": "simulated", "key_file": "k.key"}})";
    const std::pair<std::string, std::string> cases[] = {
        {"run " + both.string() + " --display offscreen --frames 1", "field 'device.key_file'"},
        {"run " + simulated.string() + " --display offscreen --frames 1", "key_file"},
        {"run --display offscreen --device simulated --key-file " + key.string() + " --frames 1",
         "--key-file: only with --device net"},
        {"device-server --passphrase-env TRIDEX_TEST_SEAL_UNSET --seconds 1",
         "--passphrase-env TRIDEX_TEST_SEAL_UNSET: the environment variable TRIDEX_TEST_SEAL_UNSET is not set"},
        {"device-server --passphrase-env TRIDEX_TEST_SEAL_EMPTY --seconds 1", "TRIDEX_TEST_SEAL_EMPTY is empty"},
        {"device-server --key-file " + (dir / "missing.key").string() + " --seconds 1", "--key-file: key file '"},
        {"device-server --key-file " + key.string() + " --passphrase-env TRIDEX_TEST_SEAL_EMPTY --seconds 1",
         "--key-file, --passphrase-env: choose one"},
        {"demo --device omni --key-file " + key.string() + " --seconds 1", "--key-file: only with --device net"},
        {"demo --device net:127.0.0.1:9 --passphrase-env TRIDEX_TEST_SEAL_UNSET --seconds 1",
         "TRIDEX_TEST_SEAL_UNSET is not set"},
    };
    for (const auto& [args, expect] : cases) {
        const auto r = run_tridex(args, dir / "run");
        EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
        EXPECT_NE(r.err.find(expect), std::string::npos) << args << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
    }
    unsetenv("TRIDEX_TEST_SEAL_EMPTY");
}

}  // namespace
