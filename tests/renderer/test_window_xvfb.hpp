// tests/renderer/test_window_xvfb.hpp - a private Xvfb X server for window tests on machines without a display.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>

namespace tridex::renderer::test {

/// Starts `Xvfb :N -displayfd FD -screen 0 <width>x<height>x24 -nolisten tcp -noreset` (no server reset when
/// the last client disconnects, which would refuse a reconnecting client) on a free display number N
/// (chosen from the process id; taken numbers are skipped and retried), waits until Xvfb writes N to FD (it
/// then accepts connections), points DISPLAY at it, and on destruction stops it (SIGTERM, then SIGKILL after
/// 5 s) and restores DISPLAY. Throws std::runtime_error when Xvfb cannot be started (not installed:
/// scripts/install-deps.sh installs it) or does not come up within 20 s.
class VirtualDisplay {
public:
    explicit VirtualDisplay(int width = 1280, int height = 1024) {
        if (const char* old = std::getenv("DISPLAY")) {
            had_display_ = true;
            old_display_ = old;
        }
        const std::string screen = std::to_string(width) + "x" + std::to_string(height) + "x24";
        // Display numbers spread by process id, so that test processes running at the same time (ctest -j)
        // do not reuse a number another server is just releasing (a dying server unlinks its socket path).
        for (int attempt = 0; attempt < 20; ++attempt) {
            const int n = 100 + static_cast<int>((static_cast<unsigned>(getpid()) * 7u + attempt * 37u) % 800u);
            struct stat st {};
            if (stat(("/tmp/.X" + std::to_string(n) + "-lock").c_str(), &st) == 0 ||
                stat(("/tmp/.X11-unix/X" + std::to_string(n)).c_str(), &st) == 0)
                continue;
            if (start(n, screen)) {
                display_ = ":" + std::to_string(n);
                setenv("DISPLAY", display_.c_str(), 1);
                return;
            }
        }
        throw std::runtime_error("VirtualDisplay: Xvfb did not start (is it installed? scripts/install-deps.sh)");
    }

    ~VirtualDisplay() {
        stop();
        if (had_display_)
            setenv("DISPLAY", old_display_.c_str(), 1);
        else
            unsetenv("DISPLAY");
    }

    VirtualDisplay(const VirtualDisplay&) = delete;
    VirtualDisplay& operator=(const VirtualDisplay&) = delete;

    /// The display name, e.g. ":3".
    const std::string& display() const { return display_; }

private:
    // Runs `Xvfb :n -displayfd FD ...` and waits (up to 20 s) until it writes its display number to FD, which
    // it does once it accepts connections. False (server stopped) when it exits early, e.g. :n was taken.
    bool start(int n, const std::string& screen) {
        int fds[2];
        if (pipe(fds) != 0) throw std::runtime_error("VirtualDisplay: pipe() failed");
        const std::string display = ":" + std::to_string(n), fd_text = std::to_string(fds[1]);
        pid_ = fork();
        if (pid_ < 0) throw std::runtime_error("VirtualDisplay: fork() failed");
        if (pid_ == 0) {
            close(fds[0]);
            const int null = open("/dev/null", O_WRONLY);
            if (null >= 0) {
                dup2(null, STDOUT_FILENO);
                dup2(null, STDERR_FILENO);
            }
            execlp("Xvfb", "Xvfb", display.c_str(), "-displayfd", fd_text.c_str(), "-screen", "0", screen.c_str(),
                   "-nolisten", "tcp", "-noreset", static_cast<char*>(nullptr));
            _exit(127);
        }
        close(fds[1]);
        std::string written;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        while (written.empty() || written.back() != '\n') {
            pollfd p{fds[0], POLLIN, 0};
            const auto left =
                std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
            if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) break;
            char c = 0;
            if (read(fds[0], &c, 1) != 1) break;  // Xvfb exited (display taken, or exec failed)
            written += c;
        }
        close(fds[0]);
        if (written == std::to_string(n) + "\n") return true;
        stop();
        return false;
    }

    void stop() {
        if (pid_ <= 0) return;
        kill(pid_, SIGTERM);
        for (int i = 0; i < 500; ++i) {
            if (waitpid(pid_, nullptr, WNOHANG) == pid_) {
                pid_ = -1;
                return;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        kill(pid_, SIGKILL);
        waitpid(pid_, nullptr, 0);
        pid_ = -1;
    }

    pid_t pid_ = -1;
    std::string display_;
    bool had_display_ = false;
    std::string old_display_;
};

}  // namespace tridex::renderer::test
