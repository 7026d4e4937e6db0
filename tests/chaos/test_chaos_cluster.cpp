// A cluster render rank killed (SIGKILL) at random frames of a three-rank wall session under mpirun: every time, rank
// 0 names the rank, ends the session in order and keeps all its work: report.json with the failure, sculpted.ply, the
// journal holding every sample the session applied, and `tridex recover` rebuilding the model from that journal.
// A cluster session can only end its render ranks through mpirun, so a run takes the config's 5 s time-out.
// TRIDEX_CHAOS_RANK_KILLS sets how many kills (default 3; the long form in docs/benchmarks/chaos.md runs 20).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include "../test_paths.hpp"
#include "chaos_env.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "cluster_launch.hpp"
#include "compute/journal/journal_reader.hpp"
#include "test_files.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

int kills_wanted() { return static_cast<int>(test::chaos_env("TRIDEX_CHAOS_RANK_KILLS", 3)); }

TEST(ChaosCluster, ARenderRankKilledAtRandomFramesNeverCostsRank0ItsWork) {
    if (!test::have_mpirun())
        GTEST_FAIL() << "mpirun is not installed (Debian's openmpi-bin; scripts/install-deps.sh installs it)";
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_chaos_cluster";
    // The session's length in frames, from a run without a fault.
    const fs::path config = test::cluster_data() / "two_tiles_quick_timeout.json";
    const test::Launch base = test::mpirun3(dir / "baseline", config);
    ASSERT_EQ(base.exit_code, 0) << base.log;
    const int frames = test::read_json(dir / "baseline" / "report.json")["cluster"]["frames"].get<int>();
    ASSERT_GT(frames, 2);
    std::mt19937 rng(static_cast<unsigned>(std::random_device{}()));
    const int kills = kills_wanted();
    int kept = 0;
    for (int k = 0; k < kills; ++k) {
        const int rank = 1 + static_cast<int>(rng() % 2);
        const int frame = 1 + static_cast<int>(rng() % static_cast<unsigned>(frames - 1));
        SCOPED_TRACE("render rank " + std::to_string(rank) + " killed at frame " + std::to_string(frame));
        const fs::path out = dir / ("kill" + std::to_string(k));
        const test::Launch l = test::mpirun3(
            out, config, "TRIDEX_CLUSTER_FAULT=" + std::to_string(rank) + ":" + std::to_string(frame) + ":kill");
        EXPECT_NE(l.exit_code, 0) << l.log;
        const std::string named = "render rank " + std::to_string(rank) + " did not answer frame ";
        EXPECT_NE(l.log.find(named), std::string::npos) << l.log;
        EXPECT_NE(l.log.find("kept its work"), std::string::npos) << l.log;
        ASSERT_TRUE(fs::exists(out / "report.json")) << l.log;
        const nlohmann::json report = test::read_json(out / "report.json");
        EXPECT_NE(report["cluster"]["failure"].get<std::string>().find("render rank " + std::to_string(rank)),
                  std::string::npos);
        EXPECT_TRUE(fs::exists(out / "sculpted.ply"));
        // Every sample the session applied is in the journal, and recover rebuilds the model from it.
        const compute::Journal journal = compute::read_journal((out / "session.tdj").string());
        std::size_t samples = 0;
        for (const compute::JournalRecord& r : journal.records) samples += r.samples.size();
        const bool all_kept = samples == report["sculpt"]["samples"].get<std::size_t>();
        EXPECT_TRUE(all_kept) << samples << " samples in the journal, " << report["sculpt"]["samples"];
        const std::string recover = std::string(TRIDEX_EXE) + " recover " + (out / "session.tdj").string() +
                                    " --out " + (out / "recovered").string() + " > " +
                                    (out / "recover.log").string() + " 2>&1";
        const bool recovered = std::system(recover.c_str()) == 0 && fs::exists(out / "recovered" / "sculpted.ply");
        EXPECT_TRUE(recovered) << "tridex recover failed: see " << (out / "recover.log");
        if (all_kept && recovered) ++kept;
        std::printf("[ chaos ] render rank %d killed at frame %d of %d: exit %d, %zu samples kept, %s\n", rank, frame,
                    frames, l.exit_code, samples, recovered ? "recovered" : "NOT recovered");
    }
    std::printf("[ chaos ] %d kills, %d sessions kept all their work\n", kills, kept);
}

}  // namespace
}  // namespace tridex::app
