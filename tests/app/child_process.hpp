// tests/app/child_process.hpp - a tridex child process whose stdout a test reads line by line (killed with SIGKILL
// and reaped when it goes out of scope), for tests that run several processes or kill one on purpose.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <regex>
#include <string>
#include <vector>

extern char** environ;

namespace tridex::app::test {

// A child process whose stdout the test reads line by line; killed (SIGKILL) and reaped when it goes out of scope.
class Child {
public:
    /// Starts args[0] with args; its stdout (and stderr too when with_stderr) goes to the pipe the test reads.
    explicit Child(const std::vector<std::string>& args, bool with_stderr = false) {
        int fds[2];
        if (pipe2(fds, O_CLOEXEC) != 0) return;
        posix_spawn_file_actions_t fa;
        posix_spawn_file_actions_init(&fa);
        posix_spawn_file_actions_adddup2(&fa, fds[1], 1);
        if (with_stderr) posix_spawn_file_actions_adddup2(&fa, fds[1], 2);
        std::vector<char*> argv;
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        if (posix_spawn(&pid_, argv[0], &fa, nullptr, argv.data(), environ) != 0) pid_ = -1;
        posix_spawn_file_actions_destroy(&fa);
        close(fds[1]);
        out_ = fds[0];
    }
    ~Child() {
        if (pid_ > 0) {
            kill(pid_, SIGKILL);
            int status = 0;
            waitpid(pid_, &status, 0);
        }
        if (out_ >= 0) close(out_);
    }
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;

    bool started() const { return pid_ > 0 && out_ >= 0; }
    // Reads stdout until a line matches `re` (its first group in `group`) or timeout_s passes; false on time-out or
    // when the child closed its stdout (exited) first.
    bool wait_for_line(const std::regex& re, double timeout_s, std::string& group) {
        using Clock = std::chrono::steady_clock;
        const auto end = Clock::now() + std::chrono::duration<double>(timeout_s);
        while (Clock::now() < end) {
            for (std::size_t nl; (nl = buffer_.find('\n')) != std::string::npos;) {
                const std::string line = buffer_.substr(0, nl);
                buffer_.erase(0, nl + 1);
                seen_ += line + "\n";
                std::smatch m;
                if (std::regex_search(line, m, re)) {
                    group = m.size() > 1 ? m[1].str() : "";
                    return true;
                }
            }
            pollfd p{out_, POLLIN, 0};
            if (poll(&p, 1, 100) <= 0) continue;
            char chunk[4096];
            const ssize_t n = read(out_, chunk, sizeof chunk);
            if (n <= 0) return false;  // the child is gone
            buffer_.append(chunk, static_cast<std::size_t>(n));
        }
        return false;
    }
    // Everything read so far (for failure messages).
    const std::string& seen() const { return seen_; }
    /// The child's process id (-1 when it did not start or was reaped).
    pid_t pid() const { return pid_; }
    /// Reads the rest of its output until it closes it (into seen()), then reaps it: its exit code, or 128 + the
    /// signal that ended it.
    int finish() {
        std::string unused;
        while (wait_for_line(std::regex("(?!)"), 3600.0, unused)) {
        }
        seen_ += buffer_;
        buffer_.clear();
        int status = 0;
        if (pid_ > 0) waitpid(pid_, &status, 0);
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    }

private:
    pid_t pid_ = -1;
    int out_ = -1;
    std::string buffer_, seen_;
};

}  // namespace tridex::app::test
