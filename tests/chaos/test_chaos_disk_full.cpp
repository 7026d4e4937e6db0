// A disk that fills at a random moment of a session: a tmpfs of a random size (64 KB to 2 MB) as the output folder
// (as root; elsewhere a file-size limit, `ulimit -f`, with SIGXFSZ ignored, so a write fails with EFBIG instead of
// ENOSPC). Every time the session runs to its end (every tick), says in one line each output it could not write,
// exits 2 when one was not written (0 when all fit), and every file it did write is whole: the pictures end in
// their IEND chunk, report.json parses and lists exactly the files there, sculpted.ply reads, haptics.csv has whole
// rows, and the journal's intact records recover. TRIDEX_CHAOS_DISKS sets how many sizes (default 4).
#include <gtest/gtest.h>

#include "../test_paths.hpp"
#include "chaos_env.hpp"

#include <sys/mount.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "test_files.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/mesh/ply_reader.hpp"
#include "core/error.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

int disks_wanted() { return static_cast<int>(test::chaos_env("TRIDEX_CHAOS_DISKS", 4)); }

// A folder of `bytes` capacity: a tmpfs mounted there (true), or false when mounting is not allowed.
bool mount_small_disk(const fs::path& at, std::uintmax_t bytes) {
    fs::create_directories(at);
    const std::string opts = "size=" + std::to_string(bytes) + ",mode=0755";
    return ::mount("tmpfs", at.c_str(), "tmpfs", 0, opts.c_str()) == 0;
}

// Checks that `file`, written by the session, is whole; a failure message, or "" when it is.
std::string whole(const fs::path& file) {
    const std::string bytes = test::bytes_of(file);
    const std::string ext = file.extension().string();
    if (ext == ".png") {
        if (bytes.size() < 20 || bytes.compare(1, 3, "PNG") != 0 || bytes.find("IEND", bytes.size() - 12) == std::string::npos)
            return file.string() + ": not a whole PNG (" + std::to_string(bytes.size()) + " bytes)";
    } else if (ext == ".json") {
        try {
            const nlohmann::json parsed = nlohmann::json::parse(bytes);
            if (parsed.is_discarded()) return file.string() + ": not whole JSON";
        } catch (const std::exception& e) {
            return file.string() + ": not whole JSON: " + e.what();
        }
    } else if (ext == ".ply") {
        try {
            (void)compute::read_ply(file.string(), bytes);
        } catch (const tridex::Error& e) {
            return file.string() + ": not a whole PLY: " + e.what();
        }
    } else if (ext == ".csv") {
        if (bytes.empty() || bytes.back() != '\n') return file.string() + ": a cut last row";
        std::istringstream in(bytes);
        std::string line;
        std::getline(in, line);
        const auto commas = std::count(line.begin(), line.end(), ',');
        for (int row = 2; std::getline(in, line); ++row)
            if (std::count(line.begin(), line.end(), ',') != commas) return file.string() + ": row " + std::to_string(row) + " is cut";
    } else if (ext == ".tdj") {
        try {
            (void)compute::read_journal(file.string());  // the header whole; a cut tail is the journal's to recover
        } catch (const tridex::Error& e) {
            return file.string() + ": " + e.what();
        }
    }
    return "";
}

TEST(ChaosDiskFull, ASessionOnADiskThatFillsRunsOnAndWritesOnlyWholeFiles) {
    const unsigned seed = static_cast<unsigned>(::getpid()) * 2654435761u;
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::uintmax_t> size_kb(64, 2048);
    const fs::path root = fs::path(testing::TempDir()) / "tridex_chaos_disk";
    int refused_some = 0, rounds = disks_wanted();
    for (int round = 0; round < rounds; ++round) {
        const std::uintmax_t kb = size_kb(rng);
        SCOPED_TRACE("seed " + std::to_string(seed) + ", a disk of " + std::to_string(kb) + " KB");
        const fs::path disk = root / ("disk_" + std::to_string(round));
        fs::remove_all(disk);
        const bool mounted = mount_small_disk(disk, kb * 1024);
        const fs::path out = disk / "session";
        const std::string demo = "demo --seconds 2 --resolution 48 --width 64 --height 48 --out " + out.string();
        // Without a tmpfs, each file is limited to the size instead (sh: ulimit -f counts 1 KB blocks).
        const std::string args = mounted ? demo
                                         : "--version >/dev/null; sh -c 'trap \"\" XFSZ; ulimit -f " + std::to_string(kb) +
                                               "; exec " + TRIDEX_EXE + " " + demo + "'";
        const test::ExeResult r = test::run_tridex(args, root / ("log_" + std::to_string(round)));
        const std::string said = r.err;
        const std::string summary = test::bytes_of(root / ("log_" + std::to_string(round)) / "stdout.txt");
        // It ran to its end: every tick of the 2 s stroke (the last one or two fall either side of its end).
        std::smatch ticks;
        ASSERT_TRUE(std::regex_search(summary, ticks, std::regex(R"(haptic loop: ([0-9]+) ticks)"))) << summary << said;
        EXPECT_GE(std::stoi(ticks[1].str()), 2000) << summary;
        // One line for each output not written, naming it; exit 2 then, else 0.
        std::set<std::string> refused;
        const std::regex line(R"(tridex: (\S+): cannot write \(([^)]*)\))");
        for (std::sregex_iterator it(said.begin(), said.end(), line), end; it != end; ++it) refused.insert((*it)[1].str());
        EXPECT_EQ(r.exit_code, refused.empty() ? 0 : 2) << said;
        if (!refused.empty()) ++refused_some;
        // Every file there is whole, and none of those refused is there.
        std::set<std::string> present;
        if (fs::exists(out))
            for (const fs::directory_entry& e : fs::directory_iterator(out)) {
                present.insert(e.path().string());
                EXPECT_EQ(whole(e.path()), "") << said;
            }
        for (const std::string& f : refused) EXPECT_EQ(present.count(f), 0u) << f << " was said not written";
        // report.json, when written, lists exactly what is there (and the journal, which runs on its own).
        if (fs::exists(out / "report.json")) {
            const nlohmann::json rep = test::read_json(out / "report.json");
            for (const auto& f : rep["files"]) EXPECT_EQ(present.count(f.get<std::string>()), 1u) << f;
        }
        // The journal that stopped when the disk filled still recovers its intact records.
        if (fs::exists(out / "session.tdj")) {
            const test::ExeResult rec =
                test::run_tridex("recover " + (out / "session.tdj").string() + " --out " + (root / "rec").string(),
                                 root / ("reclog_" + std::to_string(round)));
            EXPECT_EQ(rec.exit_code, 0) << rec.err;
        }
        if (mounted) ::umount2(disk.c_str(), MNT_DETACH);
        std::printf("[chaos disk] %s of %ju KB: %zu outputs not written, %zu written, exit %d\n",
                    mounted ? "tmpfs" : "file-size limit", kb, refused.size(), present.size(), r.exit_code);
    }
    std::printf("[chaos disk] seed %u: %d disks, %d of them filled during the session\n", seed, rounds, refused_some);
}

}  // namespace
}  // namespace tridex::app
