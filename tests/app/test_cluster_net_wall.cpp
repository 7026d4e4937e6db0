// A wall without mpirun on this machine: rank 0 listens, render ranks are processes started by hand that connect to it
// over ENet (sealed with the config's key). A render rank that comes after the start joins the running wall with the
// model as it stands; one that dies is let go and the wall goes on; a new process takes its place. Every rank still
// drawing at the end holds rank 0's model, and rank 0's journal replays to it, through an undo (after the joins) of a
// stroke made before them.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../test_paths.hpp"
#include "app/session/cluster/cluster_replica.hpp"
#include "child_process.hpp"
#include "cluster_launch.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/model/model_digest.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

using test::cluster_data;

// A UDP port nobody holds now (bound, read, closed).
std::uint16_t free_udp_port() {
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    (void)::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t n = sizeof a;
    (void)::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n);
    ::close(fd);
    return ntohs(a.sin_port);
}

using test::Child;

// `tridex run ARGS...` as a child under `timeout 200`, with `env` ("NAME=VALUE", or "") set for it alone; its stdout
// and stderr are read by the test.
std::unique_ptr<Child> tridex_child(const std::string& env, std::vector<std::string> args) {
    std::vector<std::string> argv = {"/usr/bin/env"};
    if (!env.empty()) argv.push_back(env);
    argv.insert(argv.end(), {"timeout", "200", TRIDEX_EXE, "run"});
    argv.insert(argv.end(), args.begin(), args.end());
    return std::make_unique<Child>(argv, true);
}

// Waits up to timeout_s for a line of `c`'s output holding `words` (letters, digits and spaces: a plain pattern),
// among the lines after the last one waited for.
bool wait_for(Child& c, const std::string& words, double timeout_s) {
    std::string unused;
    return c.wait_for_line(std::regex(words), timeout_s, unused);
}

std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

TEST(ClusterNetWall, RenderRanksJoinTheRunningWallAndANewProcessTakesAFailedOnesPlace) {
    const fs::path out = fs::path(testing::TempDir()) / "tridex_cluster_net";
    fs::remove_all(out);
    fs::create_directories(out);
    const std::uint16_t port = free_udp_port();
    const std::vector<std::string> common = {
        (cluster_data() / "wall_small_scene_undo.json").string(), "--display", "offscreen", "--no-items", "--cluster",
        (cluster_data() / "two_tiles_net.json").string()};
    const auto with = [&](std::vector<std::string> more) {
        std::vector<std::string> a = common;
        a.insert(a.end(), more.begin(), more.end());
        return a;
    };
    const std::string at = "127.0.0.1:" + std::to_string(port);
    const auto render_rank = [&](int rank, const std::string& env, const std::string& name) {
        return tridex_child(env, with({"--cluster-connect", at, "--rank", std::to_string(rank), "--out", (out / name).string()}));
    };
    // Rank 0 sculpts for 50 s; rank 1 starts with it; rank 2 is not there when the wall starts.
    auto root = tridex_child("", with({"--cluster-listen", at, "--seconds", "50", "--out", (out / "root").string()}));
    auto rank1 = render_rank(1, "", "rank1");
    ASSERT_TRUE(wait_for(*root, "render rank 2 has not connected", 60)) << root->seen();

    // Rank 2's first process joins the running wall, then dies at its first frame in step.
    auto first2 = render_rank(2, "TRIDEX_CLUSTER_FAULT=2:0:kill", "rank2_first");
    ASSERT_TRUE(wait_for(*root, "render rank 2 joined the wall", 60)) << root->seen();
    ASSERT_TRUE(wait_for(*root, "render rank 2 let go", 60)) << root->seen();
    EXPECT_EQ(first2->finish(), 128 + SIGKILL) << first2->seen();

    // A new process takes its place, and stays to the end.
    auto second2 = render_rank(2, "", "rank2_second");
    ASSERT_TRUE(wait_for(*root, "render rank 2 joined the wall", 120)) << root->seen();
    EXPECT_EQ(root->finish(), 0) << root->seen();
    EXPECT_EQ(rank1->finish(), 0) << rank1->seen();
    EXPECT_EQ(second2->finish(), 0) << second2->seen();

    std::ifstream in(out / "root" / "report.json");
    const nlohmann::json report = nlohmann::json::parse(in);
    const nlohmann::json& c = report["cluster"];
    EXPECT_TRUE(c["failure"].is_null()) << c["failure"];
    EXPECT_TRUE(c["open_membership"].get<bool>());
    ASSERT_EQ(c["events"].size(), 3u) << c["events"].dump(1);
    EXPECT_EQ(c["events"][0]["what"], "joined");
    EXPECT_EQ(c["events"][1]["what"], "let go");
    EXPECT_EQ(c["events"][2]["what"], "joined");
    const std::uint64_t joined_at = c["events"][2]["first_record"].get<std::uint64_t>();
    EXPECT_GT(joined_at, 0u) << "the replacement started from the model as it stood, not the session's start";
    EXPECT_GT(c["events"][2]["hello_bytes"].get<double>(), 0.0);
    EXPECT_EQ(report["history"]["undos"], 1) << "the scripted Ctrl+Z undid a stroke";

    // Both ranks drawing at the end hold the model of rank 0's journal, replayed.
    const compute::Journal journal = compute::read_journal((out / "root" / "session.tdj").string());
    std::uint64_t undo_at = 0;
    for (const compute::JournalRecord& r : journal.records)
        if (r.kind == compute::JournalKind::kUndo) undo_at = r.index;
    EXPECT_GT(undo_at, joined_at) << "the undo came after the replacement joined, of a stroke made before";
    ClusterReplica replay(journal.session);
    FrameMessage m;
    m.records = journal.records;
    ASSERT_FALSE(replay.apply(m).has_value());
    ASSERT_EQ(c["render_ranks"].size(), 2u);
    for (const nlohmann::json& rank : c["render_ranks"]) {
        EXPECT_EQ(rank["final_digest"].get<std::uint64_t>(), replay.digest()) << "rank " << rank["rank"];
        EXPECT_EQ(rank["validation_messages"], 0);
        if (rank["rank"] == 2) {
            EXPECT_EQ(rank["first_record"].get<std::uint64_t>(), joined_at);
        }
    }
    EXPECT_TRUE(fs::exists(out / "rank2_second" / "right-half" / "left.png"));
}

TEST(ClusterNetWall, AProcessWithoutTheKeyOrWithATakenRankIsTurnedAway) {
    const fs::path out = fs::path(testing::TempDir()) / "tridex_cluster_net_refused";
    fs::remove_all(out);
    fs::create_directories(out);
    const std::uint16_t port = free_udp_port();
    const std::string at = "127.0.0.1:" + std::to_string(port);
    const auto args = [&](const fs::path& config, std::vector<std::string> more) {
        std::vector<std::string> a = {(cluster_data() / "wall_small_scene.json").string(),
                                      "--display",
                                      "offscreen",
                                      "--no-items",
                                      "--cluster",
                                      config.string()};
        a.insert(a.end(), more.begin(), more.end());
        return a;
    };
    const fs::path config = cluster_data() / "two_tiles_net.json";
    auto root = tridex_child("", args(config, {"--cluster-listen", at, "--seconds", "20", "--out", (out / "root").string()}));
    auto rank1 = tridex_child("", args(config, {"--cluster-connect", at, "--rank", "1", "--out", (out / "rank1").string()}));
    ASSERT_TRUE(wait_for(*root, "render rank 2 has not connected", 60)) << root->seen();
    // Another claim of rank 1 while its process draws.
    auto twice = tridex_child("", args(config, {"--cluster-connect", at, "--rank", "1", "--out", (out / "twice").string()}));
    // A config without the key.
    nlohmann::json bare = nlohmann::json::parse(std::ifstream(config));
    bare.erase("key_file");
    const fs::path bare_path = out / "no_key.json";
    std::ofstream(bare_path) << bare.dump();
    auto keyless = tridex_child("", args(bare_path, {"--cluster-connect", at, "--rank", "2", "--out", (out / "keyless").string()}));
    EXPECT_NE(twice->finish(), 0);
    EXPECT_NE(twice->seen().find("--cluster-connect " + at + ": rank 0 refused the claim: render rank 1 is held"),
              std::string::npos) << twice->seen();
    EXPECT_NE(keyless->finish(), 0);
    EXPECT_NE(keyless->seen().find("--cluster-connect " + at + ":"), std::string::npos) << keyless->seen();
    EXPECT_EQ(root->finish(), 0) << root->seen();
    EXPECT_EQ(count(root->seen(), "joined the wall"), 0u) << "nobody joined late: " << root->seen();
    EXPECT_EQ(rank1->finish(), 0) << rank1->seen();
}

}  // namespace
}  // namespace tridex::app
