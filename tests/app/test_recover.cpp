// `tridex recover`: a session's model rebuilt from its journal after a normal end, after SIGKILL at random moments,
// from a torn tail, and refusals (a changed mesh, a file that is not a journal).
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "../test_paths.hpp"
#include "app/scene/session_spec.hpp"
#include "app/session/runtime/session_runtime.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/mesh/mesh_export.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/model/volume.hpp"
#include "compute/tools/sample_sweep.hpp"
#include "compute/tools/sweep.hpp"
#include "test_files.hpp"

extern char** environ;

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kDemoArgs{"demo", "--seconds", "3", "--resolution", "48", "--width", "32", "--height", "32", "--cpu"};

// The journal's valid prefix applied independently of recover: the workpiece from the header's spec, every sweep (and
// each of its symmetric copies) applied on its own (not in the journal's batches), a fresh contour of the result;
// written as PLY bytes.
std::string independent_ply(const fs::path& journal, const fs::path& dir) {
    const compute::Journal j = compute::read_journal(journal.string());
    const SessionSpec s = spec_from_json(j.session, journal.string());
    Workpiece wp = prepare_workpiece(s.mesh_path, s.resolution, s.stock_m, s.workpiece_centre_m);
    ToolSample prev{};
    bool have_prev = false;
    for (const compute::JournalRecord& r : j.records)
        for (const ToolSample& smp : r.samples) {
            std::vector<compute::Sweep> sweeps;
            if (have_prev)
                compute::sample_sweeps(prev, smp, nullptr, nullptr, compute::symmetry_centre(wp.model.lattice), sweeps);
            for (const compute::Sweep& sw : sweeps) compute::apply_sweep(wp.model, sw);
            prev = smp;
            have_prev = true;
        }
    compute::Contourer c(wp.model);
    c.update(wp.model);
    const fs::path ply = dir / "independent.ply";
    compute::write_ply(ply.string(), c.mesh(), c.mesh_materials());
    return test::bytes_of(ply);
}

TEST(Recover, ANormalRunsJournalRecoversTheSessionsMeshByteForByte) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_recover_normal";
    fs::remove_all(dir);
    std::string args;
    for (const std::string& a : kDemoArgs) args += a + " ";
    const test::ExeResult demo = test::run_tridex(args + "--out " + (dir / "session").string(), dir / "demo");
    ASSERT_EQ(demo.exit_code, 0) << demo.err;
    const nlohmann::json sr = test::read_json(dir / "session" / "report.json");
    ASSERT_TRUE(sr["journal"].is_object());
    EXPECT_TRUE(sr["journal"]["error"].is_null());
    EXPECT_EQ(sr["journal"]["samples"], sr["sculpt"]["samples"]);
    EXPECT_GT(sr["journal"]["flushes"].get<int>(), 1);

    const test::ExeResult rec = test::run_tridex("recover " + (dir / "session" / "session.tdj").string() + " --out " + (dir / "rec").string(), dir / "recl");
    ASSERT_EQ(rec.exit_code, 0) << rec.err;
    EXPECT_EQ(rec.err, "");
    const std::string said = test::bytes_of(dir / "recl" / "stdout.txt");
    EXPECT_NE(said.find("wrote " + (dir / "rec").string() + "/: sculpted.ply, model.tdx, report.json"), std::string::npos)
        << said;
    // The demo lists its journal among the files it wrote.
    bool journal_listed = false;
    for (const nlohmann::json& f : sr["files"]) journal_listed = journal_listed || f.get<std::string>().ends_with("session.tdj");
    EXPECT_TRUE(journal_listed) << sr["files"].dump();
    EXPECT_EQ(test::bytes_of(dir / "rec" / "sculpted.ply"), test::bytes_of(dir / "session" / "sculpted.ply"));
    EXPECT_EQ(test::bytes_of(dir / "rec" / "sculpted.ply"), independent_ply(dir / "session" / "session.tdj", dir));
    const nlohmann::json rr = test::read_json(dir / "rec" / "report.json");
    // The recovered model is saved too, and holds the recovered volume.
    const compute::TdxModel saved = compute::load_tdx((dir / "rec" / "model.tdx").string(), std::size_t{1} << 32);
    EXPECT_DOUBLE_EQ(compute::dexel_volume_m3(saved.model), rr["volume_after_m3"].get<double>());
    EXPECT_TRUE(rr["truncated_at"].is_null());
    EXPECT_EQ(rr["samples"], sr["sculpt"]["samples"]);
    EXPECT_EQ(rr["records"], sr["journal"]["records"]);
    EXPECT_EQ(rr["volume_removed_m3"].get<double>(), sr["volume_removed_m3"].get<double>());
    EXPECT_NEAR(rr["recovered_device_time_s"].get<double>(), 3.0, 0.01);

    // A torn tail: cut inside the last record; one line on stderr says where.
    const std::string all = test::bytes_of(dir / "session" / "session.tdj");
    const compute::Journal j = compute::read_journal((dir / "session" / "session.tdj").string());
    const std::uint64_t last = j.records.back().offset;
    {
        std::ofstream torn(dir / "torn.tdj", std::ios::binary);
        torn.write(all.data(), static_cast<std::streamsize>(last + 7));
    }
    const test::ExeResult cut = test::run_tridex("recover " + (dir / "torn.tdj").string() + " --out " + (dir / "torn").string(), dir / "tornl");
    ASSERT_EQ(cut.exit_code, 0) << cut.err;
    EXPECT_EQ(std::count(cut.err.begin(), cut.err.end(), '\n'), 1) << cut.err;
    EXPECT_NE(cut.err.find("cut at record " + std::to_string(j.records.size() - 1) + " (byte offset " + std::to_string(last) + ")"),
              std::string::npos)
        << cut.err;
    const nlohmann::json tr = test::read_json(dir / "torn" / "report.json");
    EXPECT_EQ(tr["truncated_at"]["record"], j.records.size() - 1);
    EXPECT_EQ(tr["truncated_at"]["byte_offset"], last);
    EXPECT_EQ(test::bytes_of(dir / "torn" / "sculpted.ply"), independent_ply(dir / "torn.tdj", dir));
}

// A session sculpted with symmetry: its journal recovers, and its recording replays, to the session's mesh byte for
// byte, and the journal holds the symmetry of every sample.
TEST(Recover, ASymmetricSessionRecoversAndReplaysByteForByte) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_recover_symmetry";
    fs::remove_all(dir);
    std::string args;
    for (const std::string& a : kDemoArgs) args += a + " ";
    const test::ExeResult demo = test::run_tridex(args + "--symmetry radial:5:z --record " + (dir / "rec.trdx").string() +
                                                      " --out " + (dir / "session").string(),
                                                  dir / "demo");
    ASSERT_EQ(demo.exit_code, 0) << demo.err;
    const nlohmann::json sr = test::read_json(dir / "session" / "report.json");
    EXPECT_EQ(sr["tool"]["symmetry"], "radial:5:z");
    EXPECT_EQ(sr["settings"]["symmetry"], "radial:5:z");
    const compute::Journal j = compute::read_journal((dir / "session" / "session.tdj").string());
    std::size_t samples = 0;
    for (const compute::JournalRecord& r : j.records)
        for (const ToolSample& s : r.samples) {
            EXPECT_EQ(to_string(s.symmetry), "radial:5:z");
            ++samples;
        }
    EXPECT_GT(samples, 1000u);
    const test::ExeResult rec = test::run_tridex("recover " + (dir / "session" / "session.tdj").string() + " --out " +
                                                     (dir / "rec").string(),
                                                 dir / "recl");
    ASSERT_EQ(rec.exit_code, 0) << rec.err;
    const std::string session_ply = test::bytes_of(dir / "session" / "sculpted.ply");
    EXPECT_EQ(test::bytes_of(dir / "rec" / "sculpted.ply"), session_ply);
    EXPECT_EQ(independent_ply(dir / "session" / "session.tdj", dir), session_ply);
    const test::ExeResult replay = test::run_tridex("replay " + (dir / "rec.trdx").string() +
                                                        " --width 32 --height 32 --cpu --out " + (dir / "replay").string(),
                                                    dir / "replayl");
    ASSERT_EQ(replay.exit_code, 0) << replay.err;
    EXPECT_EQ(test::bytes_of(dir / "replay" / "sculpted.ply"), session_ply);
    // Without the copies the journal's samples carve another model.
    const test::ExeResult plain = test::run_tridex(args + "--out " + (dir / "plain").string(), dir / "plainl");
    ASSERT_EQ(plain.exit_code, 0) << plain.err;
    EXPECT_NE(test::bytes_of(dir / "plain" / "sculpted.ply"), session_ply);
}

// One bit flipped in a batch record in the middle of the journal: recover skips that record only, says so in one line
// on stderr and in report.json, and its model is the one the remaining samples make.
TEST(Recover, ABitFlipCostsOnlyTheDamagedRecord) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_recover_flip";
    fs::remove_all(dir);
    std::string args;
    for (const std::string& a : kDemoArgs) args += a + " ";
    const test::ExeResult demo = test::run_tridex(args + "--out " + (dir / "session").string(), dir / "demo");
    ASSERT_EQ(demo.exit_code, 0) << demo.err;
    const fs::path journal = dir / "session" / "session.tdj";
    const compute::Journal j = compute::read_journal(journal.string());
    std::size_t hit = j.records.size() / 2;
    while (hit + 1 < j.records.size() && (j.records[hit].kind != compute::JournalKind::kBatch || j.records[hit].samples.empty()))
        ++hit;
    ASSERT_LT(hit + 1, j.records.size());
    const std::uint64_t size = j.records[hit + 1].offset - j.records[hit].offset;
    std::string bytes = test::bytes_of(journal);
    bytes[j.records[hit].offset + size / 2] ^= 0x10;
    {
        std::ofstream out(dir / "flipped.tdj", std::ios::binary);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    }
    // A session that ended normally holds every sample it received in its batches, intake records or not (a loaded
    // machine writes them when the sculpt thread falls behind): the damage leaves no received sample unplaced.
    EXPECT_EQ(compute::read_journal((dir / "flipped.tdj").string()).tail_unplaced, 0u);
    const test::ExeResult rec = test::run_tridex("recover " + (dir / "flipped.tdj").string() + " --out " + (dir / "rec").string(), dir / "recl");
    ASSERT_EQ(rec.exit_code, 0) << rec.err;
    EXPECT_EQ(std::count(rec.err.begin(), rec.err.end(), '\n'), 1) << rec.err;
    EXPECT_NE(rec.err.find("skipped 1 damaged record (" + std::to_string(size) + " bytes at offset " +
                           std::to_string(j.records[hit].offset) + ";"),
              std::string::npos)
        << rec.err;
    EXPECT_NE(rec.err.find("resumed at the next intact one"), std::string::npos) << rec.err;
    const nlohmann::json rr = test::read_json(dir / "rec" / "report.json");
    EXPECT_TRUE(rr["truncated_at"].is_null());
    EXPECT_EQ(rr["journal_damage"]["damaged_records"], 1);
    EXPECT_EQ(rr["journal_damage"]["skipped_bytes"], size);
    EXPECT_EQ(rr["journal_damage"]["samples_lost"], j.records[hit].samples.size());
    EXPECT_EQ(rr["journal_damage"]["marks_skipped"], 0);
    EXPECT_EQ(rr["journal_damage"]["tail_samples_unplaced"], 0);
    EXPECT_EQ(rr["samples"].get<std::uint64_t>(), j.samples - j.records[hit].samples.size());
    EXPECT_EQ(test::bytes_of(dir / "rec" / "sculpted.ply"), independent_ply(dir / "flipped.tdj", dir));
}

TEST(Recover, SessionsKilledAtRandomMomentsRecoverTheirJournalsValidPrefix) {
    const unsigned seed = static_cast<unsigned>(std::chrono::steady_clock::now().time_since_epoch().count());
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> delay_ms(1500, 4000);
    int recovered_mid_session = 0;
    for (int round = 0; round < 3; ++round) {
        const int delay = delay_ms(rng);
        SCOPED_TRACE("seed " + std::to_string(seed) + ", round " + std::to_string(round) + ", SIGKILL after " +
                     std::to_string(delay) + " ms");
        const fs::path dir = fs::path(testing::TempDir()) / ("tridex_recover_kill_" + std::to_string(round));
        fs::remove_all(dir);
        fs::create_directories(dir);
        std::vector<std::string> args{TRIDEX_EXE};
        args.insert(args.end(), kDemoArgs.begin(), kDemoArgs.end());
        args.push_back("--out");
        args.push_back((dir / "session").string());
        std::vector<char*> argv;
        for (std::string& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        posix_spawn_file_actions_t fa;
        posix_spawn_file_actions_init(&fa);
        posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
        pid_t pid = 0;
        ASSERT_EQ(posix_spawn(&pid, TRIDEX_EXE, &fa, nullptr, argv.data(), environ), 0);
        posix_spawn_file_actions_destroy(&fa);
        std::this_thread::sleep_for(std::chrono::milliseconds(delay));
        ::kill(pid, SIGKILL);
        int status = 0;
        ASSERT_EQ(::waitpid(pid, &status, 0), pid);
        const bool killed = WIFSIGNALED(status);
        const fs::path journal = dir / "session" / "session.tdj";
        if (!fs::exists(journal)) {  // killed before the session started: nothing to recover
            EXPECT_TRUE(killed);
            continue;
        }
        const test::ExeResult rec = test::run_tridex("recover " + journal.string() + " --out " + (dir / "rec").string(), dir / "recl");
        if (rec.exit_code != 0) {
            // Only a header that never reached the disk may be refused.
            EXPECT_NE(rec.err.find("header"), std::string::npos) << rec.err;
            EXPECT_LT(fs::file_size(journal), 4096u);
            continue;
        }
        EXPECT_EQ(test::bytes_of(dir / "rec" / "sculpted.ply"), independent_ply(journal, dir));
        if (killed)
            ++recovered_mid_session;
        else  // the session ended before the kill: recovery gives its own mesh
            EXPECT_EQ(test::bytes_of(dir / "rec" / "sculpted.ply"), test::bytes_of(dir / "session" / "sculpted.ply"));
    }
    std::printf("seed %u: %d of 3 sessions killed mid-way and recovered\n", seed, recovered_mid_session);
}

TEST(Recover, RefusesAChangedMeshAndFilesThatAreNotJournals) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_recover_refuse";
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::copy_file(fs::path(std::getenv("TRIDEX_ASSETS")) / "bunny.off", dir / "bunny.off");
    const test::ExeResult demo = test::run_tridex("demo --seconds 1 --resolution 32 --width 16 --height 16 --cpu --mesh " +
                                       (dir / "bunny.off").string() + " --journal " + (dir / "j.tdj").string() +
                                       " --out " + (dir / "session").string(),
                                   dir / "demo");
    ASSERT_EQ(demo.exit_code, 0) << demo.err;
    EXPECT_FALSE(fs::exists(dir / "session" / "session.tdj"));
    {
        std::ofstream more(dir / "bunny.off", std::ios::app);
        more << "\n";
    }
    const test::ExeResult changed = test::run_tridex("recover " + (dir / "j.tdj").string() + " --out " + (dir / "rec").string(), dir / "r1");
    EXPECT_EQ(changed.exit_code, 2);
    EXPECT_EQ(std::count(changed.err.begin(), changed.err.end(), '\n'), 1) << changed.err;
    EXPECT_NE(changed.err.find("changed since the session"), std::string::npos) << changed.err;

    {
        std::ofstream junk(dir / "junk.tdj");
        junk << "not a journal at all\n";
    }
    const test::ExeResult junk = test::run_tridex("recover " + (dir / "junk.tdj").string() + " --out " + (dir / "rec2").string(), dir / "r2");
    EXPECT_EQ(junk.exit_code, 2);
    EXPECT_EQ(junk.err, "tridex: " + (dir / "junk.tdj").string() + ": not a tridex session journal (no TRDXJNL header)\n");

    const test::ExeResult off = test::run_tridex("demo --seconds 1 --resolution 32 --width 16 --height 16 --cpu --no-journal --out " +
                                      (dir / "nj").string(),
                                  dir / "demo2");
    ASSERT_EQ(off.exit_code, 0) << off.err;
    EXPECT_FALSE(fs::exists(dir / "nj" / "session.tdj"));
    EXPECT_TRUE(test::read_json(dir / "nj" / "report.json")["journal"].is_null());
}

}  // namespace
}  // namespace tridex::app
