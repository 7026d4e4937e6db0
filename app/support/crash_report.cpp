// app/support/crash_report.cpp - fatal-signal handlers that report before the default action (Linux, glibc).
#include "app/support/crash_report.hpp"

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <mutex>

#if defined(__linux__)
#include <execinfo.h>
#include <sys/prctl.h>
#include <unistd.h>
#endif

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define TRIDEX_CRASH_REPORT_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define TRIDEX_CRASH_REPORT_SANITIZED 1
#endif
#endif

namespace tridex::app {
namespace {

constexpr std::size_t kNoteBytes = 1024;
constexpr int kMaxFrames = 64;

// Two note buffers: set_crash_note() fills the one not published, then publishes it, so the handler never reads a
// note while it is being written (a third writer waits on the mutex).
char notes[2][kNoteBytes];
std::atomic<int> published{-1};
std::mutex note_mutex;

constexpr int kSignals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};

const char* signal_name(int sig) {
    switch (sig) {
        case SIGSEGV: return "SIGSEGV";
        case SIGBUS: return "SIGBUS";
        case SIGFPE: return "SIGFPE";
        case SIGILL: return "SIGILL";
        case SIGABRT: return "SIGABRT";
        default: return "a fatal signal";
    }
}

void put(int fd, const char* s) {
#if defined(__linux__)
    std::size_t left = std::strlen(s);
    while (left > 0) {
        const ssize_t n = ::write(fd, s, left);
        if (n <= 0) return;
        s += n;
        left -= static_cast<std::size_t>(n);
    }
#else
    (void)fd;
    (void)s;
#endif
}

void put_hex(int fd, std::uintptr_t v) {
    char out[2 + 2 * sizeof v + 1];
    char* p = out + sizeof out - 1;
    *p = '\0';
    do {
        *--p = "0123456789abcdef"[v & 0xf];
        v >>= 4;
    } while (v != 0);
    *--p = 'x';
    *--p = '0';
    put(fd, p);
}

// Unused in a sanitized build, which keeps the sanitizer's own report (install_crash_report).
[[maybe_unused]] void on_fatal_signal(int sig, siginfo_t* info, void*) {
    const bool fault = sig == SIGSEGV || sig == SIGBUS || sig == SIGFPE || sig == SIGILL;
    // si_addr means something only for a fault the kernel raised (si_code > 0), not for kill() or raise().
    write_crash_report(STDERR_FILENO, sig, fault && info && info->si_code > 0 ? info->si_addr : nullptr);
    // SA_RESETHAND restored the default action; the signal is blocked while the handler runs, so this one is
    // delivered when it returns (a fault that returns would also fault again).
    std::raise(sig);
}

}  // namespace

void write_crash_report(int fd, int signal, const void* address) {
    put(fd, "tridex: crashed: ");
    put(fd, signal_name(signal));
    if (address) {
        put(fd, " at address ");
        put_hex(fd, reinterpret_cast<std::uintptr_t>(address));
    }
#if defined(__linux__)
    char thread[17] = {};
    if (prctl(PR_GET_NAME, thread, 0, 0, 0) == 0 && thread[0]) {
        put(fd, " on thread ");
        put(fd, thread);
    }
#endif
    put(fd, "\n");
    if (const int i = published.load(std::memory_order_acquire); i >= 0 && notes[i][0]) {
        put(fd, "tridex: ");
        put(fd, notes[i]);
        put(fd, "\n");
    }
#if defined(__linux__)
    void* frames[kMaxFrames];
    const int n = backtrace(frames, kMaxFrames);
    put(fd, "tridex: call stack (addresses: addr2line -f -C -e <the tridex binary> ADDRESS):\n");
    backtrace_symbols_fd(frames, n, fd);
#endif
}

void set_crash_note(const std::string& note) {
    const std::lock_guard<std::mutex> lock(note_mutex);
    const int next = published.load(std::memory_order_relaxed) == 0 ? 1 : 0;
    const std::size_t n = std::min(note.size(), kNoteBytes - 1);
    std::memcpy(notes[next], note.data(), n);
    notes[next][n] = '\0';
    published.store(next, std::memory_order_release);
}

bool install_crash_report() {
#if defined(__linux__) && !defined(TRIDEX_CRASH_REPORT_SANITIZED)
    static const bool installed = [] {
        void* warm[1];
        (void)backtrace(warm, 1);  // loads libgcc's unwinder now, not inside a handler
        struct sigaction sa {};
        sa.sa_sigaction = on_fatal_signal;
        sa.sa_flags = SA_SIGINFO | SA_RESETHAND;
        sigemptyset(&sa.sa_mask);
        bool all = true;
        for (const int sig : kSignals) all = sigaction(sig, &sa, nullptr) == 0 && all;
        return all;
    }();
    return installed;
#else
    return false;
#endif
}

}  // namespace tridex::app
