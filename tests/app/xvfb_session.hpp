// tests/app/xvfb_session.hpp - driving the real `tridex` executable in a window under a private Xvfb with X input
// events from xdotool (XTEST): the process, xdotool calls and waiting for what the window should do.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include "../test_paths.hpp"

namespace tridex::app::test {

/// True when `name` is a program on PATH.
inline bool have_binary(const char* name) {
    return std::system(("command -v " + std::string(name) + " > /dev/null 2>&1").c_str()) == 0;
}

/// Runs `xdotool ARGS` (under a 120 s timeout); its stdout, trimmed. Throws std::runtime_error with what it said
/// when it fails.
inline std::string xdo(const std::string& args) {
    const std::string cmd = "timeout 120 xdotool " + args + " 2>&1";
    std::unique_ptr<FILE, int (*)(FILE*)> p(popen(cmd.c_str(), "r"), pclose);
    if (!p) throw std::runtime_error("popen failed");
    std::string out;
    char buf[256];
    while (std::fgets(buf, sizeof buf, p.get())) out += buf;
    const int status = pclose(p.release());
    while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
    if (status != 0) throw std::runtime_error("xdotool " + args + " failed: " + out);
    return out;
}

/// Waits up to timeout_s (generous: the machine is shared) until pred() holds; false on timeout.
inline bool wait_for(const std::function<bool()>& pred, double timeout_s = 180.0) {
    const auto t0 = std::chrono::steady_clock::now();
    while (!pred()) {
        if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > timeout_s) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return true;
}

/// The first visible window whose name matches `name` (xdotool search, waiting for it), focused when a window
/// manager lets it be (without one the focus follows the pointer).
inline std::string find_window(const std::string& name) {
    const std::string found = xdo("search --sync --onlyvisible --name '" + name + "'");
    const std::string w = found.substr(0, found.find('\n'));
    try {
        xdo("windowfocus --sync " + w);
    } catch (const std::exception&) {
    }
    return w;
}

/// The `tridex` executable (TRIDEX_EXE) run with `args` through /bin/sh, stdout and stderr into dir/stdout.txt and
/// dir/stderr.txt; killed (SIGKILL) when still running at destruction.
class TridexProcess {
public:
    TridexProcess(const std::string& exe, const std::string& args, const std::filesystem::path& dir) {
        const std::string cmd = "exec " + exe + " " + args + " > " + (dir / "stdout.txt").string() + " 2> " +
                                (dir / "stderr.txt").string();
        pid_ = fork();
        if (pid_ == 0) {
            execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
            _exit(127);
        }
    }
    ~TridexProcess() {
        if (pid_ > 0) {
            kill(pid_, SIGKILL);
            waitpid(pid_, nullptr, 0);
        }
    }
    TridexProcess(const TridexProcess&) = delete;
    TridexProcess& operator=(const TridexProcess&) = delete;
    /// True until the process has exited (then exit_code() holds its status).
    bool running() {
        if (pid_ <= 0) return false;
        int status = 0;
        if (waitpid(pid_, &status, WNOHANG) != pid_) return true;
        exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        pid_ = -1;
        return false;
    }
    /// The exit status once running() returned false; -1 before, or after a signal.
    int exit_code() const { return exit_code_; }

private:
    pid_t pid_ = -1;
    int exit_code_ = -1;
};

}  // namespace tridex::app::test
