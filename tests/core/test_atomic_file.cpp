// Tests of core/atomic_file: the target holds the old or the whole new content, never a cut file; a write that
// fails (a file-size limit standing in for a full disk) names the file and leaves the old content; a writer killed
// by SIGKILL before its commit leaves no file behind (the temporary file is unnamed: O_TMPFILE).
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace tridex {
namespace {

namespace fs = std::filesystem;

std::string read_all(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

fs::path fresh_dir(const char* name) {
    const fs::path d = fs::temp_directory_path() / (std::string("tridex_") + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

TEST(AtomicFile, ReplacesTheTargetOnlyOnCommit) {
    const fs::path dir = fresh_dir("atomic");
    const fs::path target = dir / "out.bin";
    std::ofstream(target) << "old";
    {
        AtomicFile f(target.string());
        f.write("new content");
        EXPECT_EQ(read_all(target), "old");  // not yet
    }  // no commit: the temporary file is removed, the target untouched
    EXPECT_EQ(read_all(target), "old");
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
    write_file_atomically(target.string(), "new content");
    EXPECT_EQ(read_all(target), "new content");
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
    AtomicFile g(target.string());
    std::fprintf(g.stream(), "%d,%d\n", 1, 2);
    g.commit();
    EXPECT_EQ(read_all(target), "1,2\n");
    EXPECT_THROW(g.commit(), Error);
}

TEST(AtomicFile, UncreatableFileNamesThePath) {
    try {
        AtomicFile f("/no/such/folder/out.png");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("/no/such/folder/out.png: cannot create"), std::string::npos) << e.what();
    }
}

// In a child process limited to 16 KiB per file (RLIMIT_FSIZE; SIGXFSZ ignored so the write fails with EFBIG, as a
// full disk fails with ENOSPC): a 1 MiB write fails, names the file, and the old content stays.
TEST(AtomicFile, AFailedWriteLeavesTheOldFile) {
    const fs::path dir = fresh_dir("atomic_full");
    const fs::path target = dir / "left.png";
    std::ofstream(target) << "previous picture";
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        std::signal(SIGXFSZ, SIG_IGN);
        rlimit lim{16 * 1024, 16 * 1024};
        ::setrlimit(RLIMIT_FSIZE, &lim);
        int code = 1;
        try {
            write_file_atomically(target.string(), std::string(1 << 20, 'x'));
        } catch (const Error& e) {
            const std::string m = e.what();
            code = m.find(target.string() + ": cannot write") != std::string::npos ? 0 : 2;
        }
        ::_exit(code);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "1: no error; 2: the error did not name the file";
    EXPECT_EQ(read_all(target), "previous picture");
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1) << "a temporary file was left";
}


// A writer killed by SIGKILL in the middle of its write leaves the folder as it was: the bytes went to an unnamed file
// (O_TMPFILE, which ext4 and tmpfs have), which the kernel frees with the process. Before, "<path>.tmp-<pid>" stayed.
TEST(AtomicFile, AWriterKilledBeforeItsCommitLeavesNoFile) {
    for (const fs::path& base : {fs::temp_directory_path(), fs::path("/dev/shm")}) {
        if (!fs::is_directory(base)) continue;
        const fs::path dir = base / ("tridex_atomic_kill_" + std::to_string(::getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
        const fs::path target = dir / "session.trdx";
        std::ofstream(target) << "previous recording";
        {
            AtomicFile probe((dir / "probe").string());
            EXPECT_TRUE(probe.unnamed()) << base << ": no O_TMPFILE here, the temporary file has a name";
            EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1)
                << "an unnamed temporary file showed in the folder";
        }
        int pipe_fd[2];
        ASSERT_EQ(::pipe(pipe_fd), 0);
        const pid_t pid = ::fork();
        ASSERT_GE(pid, 0);
        if (pid == 0) {
            ::close(pipe_fd[0]);
            AtomicFile f(target.string());
            f.write(std::string(1 << 20, 'x'));
            std::fflush(f.stream());
            const char ready = 1;
            (void)!::write(pipe_fd[1], &ready, 1);
            for (;;) ::pause();  // killed here, mid-session
        }
        ::close(pipe_fd[1]);
        char ready = 0;
        ASSERT_EQ(::read(pipe_fd[0], &ready, 1), 1);
        ::close(pipe_fd[0]);
        ::kill(pid, SIGKILL);
        int status = 0;
        ASSERT_EQ(::waitpid(pid, &status, 0), pid);
        EXPECT_TRUE(WIFSIGNALED(status));
        EXPECT_EQ(read_all(target), "previous recording");
        std::string names;
        for (const auto& e : fs::directory_iterator(dir)) names += " " + e.path().filename().string();
        EXPECT_EQ(names, " session.trdx") << base << ": the killed writer left files behind";
        fs::remove_all(dir);
    }
}

TEST(AtomicFile, AnUnnamedFileIsCommittedOverAnExistingTarget) {
    const fs::path dir = fresh_dir("atomic_unnamed");
    const fs::path target = dir / "model.tdx";
    std::ofstream(target) << "old";
    // A stale temporary name of this pid (an earlier process) does not stop the commit and is gone after it.
    std::ofstream(temp_path_for(target.string())) << "stale";
    AtomicFile f(target.string());
    ASSERT_TRUE(f.unnamed());
    f.write("new");
    f.commit();
    EXPECT_EQ(read_all(target), "new");
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex
