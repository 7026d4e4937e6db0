// `tridex run --host` and two `tridex run --join` as processes over ENet on loopback, each offscreen with the default
// scene's scripted hand carving the same stroke at once: every site ends with the model of a replay of the host's
// journal from its starting model, bit for bit, also a joiner killed mid-stroke and joined again; a peer with another
// key is refused; a cluster wall under mpirun joins as one site and every one of its ranks ends with the host's model.
#include <gtest/gtest.h>

#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "../test_paths.hpp"
#include "child_process.hpp"
#include "cluster_launch.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/model/tdx_file.hpp"
#include "test_files.hpp"

namespace {

namespace fs = std::filesystem;
using tridex::app::test::Child;
using tridex::app::test::read_json;

fs::path test_dir(const std::string& name) { return tridex::app::test::fresh_test_dir("tridex_shared_", name); }

fs::path key_file(const fs::path& dir, const std::string& name, const char* b) {
    return tridex::app::test::hex_key_file(dir, name, b);
}

std::vector<std::string> site_args(const std::vector<std::string>& role, const fs::path& key, const fs::path& out) {
    std::vector<std::string> a = {TRIDEX_EXE, "run", "--display", "offscreen", "--shared-key-file", key.string(),
                                  "--out", out.string(), "--save", (out / "final.tdx").string()};
    a.insert(a.end(), role.begin(), role.end());
    return a;
}

std::uint64_t digest_of_tdx(const fs::path& p) {
    const tridex::compute::TdxModel m = tridex::compute::load_tdx(p.string(), std::size_t{1} << 32);
    return tridex::compute::model_digest(m.model);
}

// The host's journal replayed on its starting model: what every site must hold.
std::uint64_t replayed_host(const fs::path& host_out) {
    tridex::compute::TdxModel m = tridex::compute::load_tdx((host_out / "shared_start.tdx").string(), std::size_t{1} << 32);
    const tridex::compute::Journal j = tridex::compute::read_journal((host_out / "session.tdj").string());
    tridex::compute::journal_apply(m.model, j.records);
    return tridex::compute::model_digest(m.model);
}

TEST(SharedSession, AHostAndTwoJoinersCarvingAtOnceEndWithTheHostsModelAndAStrangerIsRefused) {
    const fs::path dir = test_dir("three");
    const fs::path key = key_file(dir, "session.key", "5a");
    const fs::path other = key_file(dir, "other.key", "a5");
    Child host(site_args({"--host", "127.0.0.1:0", "--name", "Ann", "--seconds", "25"}, key, dir / "host"), true);
    std::string port;
    ASSERT_TRUE(host.wait_for_line(std::regex(R"(shared session on 127\.0\.0\.1:([0-9]+);)"), 120.0, port)) << host.seen();
    const std::string at = "127.0.0.1:" + port;
    Child bo(site_args({"--join", at, "--name", "Bo"}, key, dir / "bo"), true);
    Child cy(site_args({"--join", at, "--name", "Cy"}, key, dir / "cy_first"), true);
    std::string unused;
    ASSERT_TRUE(cy.wait_for_line(std::regex("joined Ann's shared session"), 120.0, unused)) << cy.seen();
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // Cy is mid-stroke
    kill(cy.pid(), SIGKILL);
    cy.finish();
    Child cy_again(site_args({"--join", at, "--name", "Cy"}, key, dir / "cy"), true);
    Child stranger(site_args({"--join", at, "--name", "Eve"}, other, dir / "eve"), true);
    const int eve_code = stranger.finish();
    EXPECT_EQ(eve_code, 2) << stranger.seen();
    EXPECT_NE(stranger.seen().find("handshake"), std::string::npos) << stranger.seen();

    EXPECT_EQ(host.finish(), 0) << host.seen();
    EXPECT_EQ(bo.finish(), 0) << bo.seen();
    EXPECT_EQ(cy_again.finish(), 0) << cy_again.seen();

    const std::uint64_t want = replayed_host(dir / "host");
    for (const char* site : {"host", "bo", "cy"}) {
        const nlohmann::json r = read_json(dir / site / "report.json");
        ASSERT_TRUE(r.contains("shared")) << site;
        EXPECT_EQ(r["shared"]["final_digest"].get<std::uint64_t>(), want) << site;
        EXPECT_EQ(digest_of_tdx(dir / site / "final.tdx"), want) << site;
        if (std::string(site) != "host") {
            EXPECT_TRUE(r["shared"]["digest_match"].get<bool>()) << site;
            EXPECT_GT(r["shared"]["samples_sent"].get<std::uint64_t>(), 1000u) << site;
            EXPECT_GT(r["shared"]["digest_checks"].get<std::uint64_t>(), 0u) << site;
        }
    }
    const nlohmann::json h = read_json(dir / "host" / "report.json")["shared"];
    EXPECT_GE(h["peers_refused"].get<std::uint64_t>(), 1u);
    int cy_sites = 0;
    for (const nlohmann::json& j : h["joiners"]) cy_sites += j["name"] == "Cy";
    EXPECT_EQ(cy_sites, 2);  // the first link and the rejoin, the same site
    // Every site's samples carved: the host's journal holds samples of the three sites.
    const tridex::compute::Journal j = tridex::compute::read_journal((dir / "host" / "session.tdj").string());
    std::vector<int> per_site(16, 0);
    for (const auto& r : j.records)
        for (const auto& s : r.samples) ++per_site[s.site];
    EXPECT_GT(per_site[0], 1000);
    EXPECT_GT(per_site[1], 1000);
    EXPECT_GT(per_site[2], 1000);
}

TEST(SharedSession, AClusterWallJoinsAsOneSiteAndEveryRankHoldsTheHostsModel) {
    if (!tridex::app::test::have_mpirun())
        GTEST_SKIP() << "mpirun is not installed (Debian's openmpi-bin; scripts/install-deps.sh installs it)";
    const fs::path dir = test_dir("wall");
    const fs::path key = key_file(dir, "session.key", "3c");
    const fs::path scene = tridex::app::test::cluster_data() / "wall_small_scene.json";
    Child host(site_args({scene.string(), "--host", "127.0.0.1:0", "--name", "Ann", "--seconds", "15"}, key, dir / "host"),
               true);
    std::string port;
    ASSERT_TRUE(host.wait_for_line(std::regex(R"(shared session on 127\.0\.0\.1:([0-9]+);)"), 120.0, port)) << host.seen();
    // The wall: rank 0 joins and sculpts with the scene's scripted hand, ranks 1 and 2 draw the two halves.
    const fs::path wall = dir / "wall";
    const std::string root = geteuid() == 0 ? " --allow-run-as-root" : "";
    const std::string cmd = "timeout 300 mpirun" + root + " --oversubscribe --mca orte_abort_on_non_zero_status 0 -np 3 " +
                            std::string(TRIDEX_EXE) + " run " + scene.string() + " --display offscreen --no-items --cluster " +
                            (tridex::app::test::cluster_data() / "two_tiles.json").string() + " --join 127.0.0.1:" + port +
                            " --shared-key-file " + key.string() + " --name Wall --out " + wall.string() + " --save " +
                            (wall / "final.tdx").string() + " > " + (dir / "wall.log").string() + " 2>&1";
    const int status = std::system(cmd.c_str());
    std::ifstream log_in(dir / "wall.log");
    const std::string log{std::istreambuf_iterator<char>(log_in), {}};
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << log;
    EXPECT_EQ(host.finish(), 0) << host.seen();

    const std::uint64_t want = replayed_host(dir / "host");
    EXPECT_EQ(read_json(dir / "host" / "report.json")["shared"]["final_digest"].get<std::uint64_t>(), want);
    const nlohmann::json w = read_json(wall / "report.json");
    EXPECT_EQ(w["shared"]["final_digest"].get<std::uint64_t>(), want);
    EXPECT_TRUE(w["shared"]["digest_match"].get<bool>());
    EXPECT_EQ(digest_of_tdx(wall / "final.tdx"), want);
    ASSERT_EQ(w["cluster"]["render_ranks"].size(), 2u) << log;
    for (const nlohmann::json& r : w["cluster"]["render_ranks"]) {
        EXPECT_EQ(r["final_digest"].get<std::uint64_t>(), want) << "render rank " << r["rank"];
        EXPECT_EQ(r["validation_messages"].get<int>(), 0);
        EXPECT_EQ(r["other_sites_last_frame"].get<int>(), 1);  // Ann, drawn on the wall's projectors too
    }
    // Each render rank built its replica from the model bytes rank 0 sent (the host's starting model).
    EXPECT_TRUE(fs::exists(wall / "cluster_start_rank1.tdx"));
    EXPECT_TRUE(fs::exists(wall / "cluster_start_rank2.tdx"));
    const tridex::compute::Journal j = tridex::compute::read_journal((dir / "host" / "session.tdj").string());
    std::uint64_t wall_samples = 0;
    for (const auto& r : j.records)
        for (const auto& s : r.samples) wall_samples += s.site == 1;
    EXPECT_GT(wall_samples, 500u);  // the wall's hand carved through the host
}

}  // namespace
