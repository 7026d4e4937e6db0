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
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "app/session/cluster/cluster_replica.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/model/model_digest.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

const fs::path kData = fs::path(TRIDEX_SOURCE_DIR) / "tests" / "data" / "cluster";

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

// A process running `cmd` under sh, its output in `log`.
struct Proc {
    pid_t pid = -1;
    fs::path log;
    int status = -1;
    bool done = false;

    Proc(const std::string& cmd, fs::path log_path) : log(std::move(log_path)) {
        const std::string line = cmd + " > " + log.string() + " 2>&1";
        pid = ::fork();
        if (pid == 0) {
            ::execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
            ::_exit(127);
        }
    }
    ~Proc() {
        if (!done && pid > 0) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, &status, 0);
        }
    }
    // True once it ended (its exit code in code()).
    bool ended() {
        if (!done && ::waitpid(pid, &status, WNOHANG) == pid) done = true;
        return done;
    }
    bool wait_s(double s) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(s);
        while (!ended() && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(50));
        return done;
    }
    int code() const { return done && WIFEXITED(status) ? WEXITSTATUS(status) : -1; }
    std::string text() const {
        std::ifstream in(log);
        return {std::istreambuf_iterator<char>(in), {}};
    }
    // Waits up to `s` seconds until its output holds `what`.
    bool wait_for_text(const std::string& what, double s) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(s);
        while (text().find(what) == std::string::npos) {
            if (std::chrono::steady_clock::now() >= until) return false;
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
        return true;
    }
};

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
    const std::string common = std::string(TRIDEX_EXE) + " run " + (kData / "wall_small_scene_undo.json").string() +
                               " --display offscreen --no-items --cluster " + (kData / "two_tiles_net.json").string();
    const auto render_rank = [&](int rank, const std::string& env, const std::string& name) {
        return std::make_unique<Proc>(env + " timeout 200 " + common + " --cluster-connect 127.0.0.1:" +
                                          std::to_string(port) + " --rank " + std::to_string(rank) + " --out " +
                                          (out / name).string(),
                                      out / (name + ".log"));
    };
    // Rank 0 sculpts for 50 s; rank 1 starts with it; rank 2 is not there when the wall starts.
    Proc root("timeout 200 " + common + " --cluster-listen 127.0.0.1:" + std::to_string(port) + " --seconds 50 --out " +
                  (out / "root").string(),
              out / "root.log");
    auto rank1 = render_rank(1, "", "rank1");
    ASSERT_TRUE(root.wait_for_text("render rank 2 has not connected", 60)) << root.text();

    // Rank 2's first process joins the running wall, then dies at its first frame in step.
    auto first2 = render_rank(2, "TRIDEX_CLUSTER_FAULT=2:0:kill", "rank2_first");
    ASSERT_TRUE(root.wait_for_text("render rank 2 joined the wall", 60)) << root.text() << first2->text();
    ASSERT_TRUE(root.wait_for_text("render rank 2 let go", 60)) << root.text();
    EXPECT_TRUE(first2->wait_s(30));

    // A new process takes its place, and stays to the end.
    auto second2 = render_rank(2, "", "rank2_second");
    ASSERT_TRUE(root.wait_s(180)) << "rank 0 did not end";
    EXPECT_EQ(root.code(), 0) << root.text();
    ASSERT_TRUE(rank1->wait_s(60));
    ASSERT_TRUE(second2->wait_s(60));
    EXPECT_EQ(rank1->code(), 0) << rank1->text();
    EXPECT_EQ(second2->code(), 0) << second2->text();
    EXPECT_EQ(count(root.text(), "render rank 2 joined the wall"), 2u) << root.text();

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
    const std::string scene = (kData / "wall_small_scene.json").string();
    const std::string common = std::string(TRIDEX_EXE) + " run " + scene + " --display offscreen --no-items --cluster ";
    Proc root("timeout 120 " + common + (kData / "two_tiles_net.json").string() + " --cluster-listen 127.0.0.1:" +
                  std::to_string(port) + " --seconds 20 --out " + (out / "root").string(),
              out / "root.log");
    Proc rank1("timeout 120 " + common + (kData / "two_tiles_net.json").string() + " --cluster-connect 127.0.0.1:" +
                   std::to_string(port) + " --rank 1 --out " + (out / "rank1").string(),
               out / "rank1.log");
    ASSERT_TRUE(root.wait_for_text("render rank 2 has not connected", 60)) << root.text();
    // Another claim of rank 1 while its process draws.
    Proc twice("timeout 60 " + common + (kData / "two_tiles_net.json").string() + " --cluster-connect 127.0.0.1:" +
                   std::to_string(port) + " --rank 1 --out " + (out / "twice").string(),
               out / "twice.log");
    // A config without the key.
    nlohmann::json bare = nlohmann::json::parse(std::ifstream(kData / "two_tiles_net.json"));
    bare.erase("key_file");
    const fs::path bare_path = out / "no_key.json";
    std::ofstream(bare_path) << bare.dump();
    Proc keyless("timeout 60 " + common + bare_path.string() + " --cluster-connect 127.0.0.1:" + std::to_string(port) +
                     " --rank 2 --out " + (out / "keyless").string(),
                 out / "keyless.log");
    ASSERT_TRUE(twice.wait_s(60));
    ASSERT_TRUE(keyless.wait_s(60));
    EXPECT_NE(twice.code(), 0);
    EXPECT_NE(twice.text().find("--cluster-connect 127.0.0.1:" + std::to_string(port)), std::string::npos) << twice.text();
    EXPECT_NE(twice.text().find("rank 1"), std::string::npos) << twice.text();
    EXPECT_NE(keyless.code(), 0);
    EXPECT_NE(keyless.text().find("--cluster-connect"), std::string::npos) << keyless.text();
    ASSERT_TRUE(root.wait_s(100));
    EXPECT_EQ(root.code(), 0) << root.text();
    EXPECT_EQ(count(root.text(), "joined the wall"), 0u) << "nobody joined late: " << root.text();
    ASSERT_TRUE(rank1.wait_s(60));
    EXPECT_EQ(rank1.code(), 0) << rank1.text();
}

}  // namespace
}  // namespace tridex::app
