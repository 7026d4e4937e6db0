// app/support/stop_signal.cpp - the SIGINT / SIGTERM flag.
#include "app/support/stop_signal.hpp"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <unistd.h>

namespace tridex::app {

namespace {

std::atomic<int> g_signal{0};
std::atomic<long long> g_first_ns{0};  // CLOCK_MONOTONIC time of the first signal
std::atomic<const char*> g_set_up_phase{nullptr};  // non-null inside a StopEndsSetUp scope
static_assert(std::atomic<const char*>::is_always_lock_free, "the phase must be lock-free to be read from a handler");
static_assert(std::atomic<int>::is_always_lock_free, "the signal flag must be lock-free to be set from a handler");
static_assert(std::atomic<long long>::is_always_lock_free, "the signal time must be lock-free to be set from a handler");

// One event can reach the process twice (`timeout` signals its child and then the child's process group); only a
// signal this long after the first counts as the user insisting.
constexpr long long kRepeat_ns = 1'000'000'000;

long long now_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);  // async-signal-safe
    return static_cast<long long>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

const char* signal_name(int sig) { return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "signal"; }

// Says which phase the signal stopped and ends the process: async-signal-safe (write and _exit only).
[[noreturn]] void end_set_up(int sig, const char* phase) {
    const char* parts[] = {"tridex: ", signal_name(sig), " while ", phase, ": nothing to keep, stopped\n"};
    for (const char* p : parts) {
        const ssize_t ignored = ::write(STDERR_FILENO, p, std::strlen(p));
        (void)ignored;
    }
    ::_exit(128 + sig);
}

extern "C" void on_stop_signal(int sig) {
    if (const char* phase = g_set_up_phase.load(std::memory_order_acquire)) end_set_up(sig, phase);
    int expected = 0;
    if (g_signal.compare_exchange_strong(expected, sig)) {
        g_first_ns.store(now_ns(), std::memory_order_release);
        return;
    }
    if (now_ns() - g_first_ns.load(std::memory_order_acquire) < kRepeat_ns) return;
    // The user asked again: the default action (terminate) at once.
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

}  // namespace

void install_stop_handlers() {
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

bool stop_requested() { return g_signal.load(std::memory_order_acquire) != 0; }

int stop_signal() { return g_signal.load(std::memory_order_acquire); }

const char* stop_signal_name() {
    switch (stop_signal()) {
        case SIGINT: return "SIGINT";
        case SIGTERM: return "SIGTERM";
        default: return "";
    }
}

StopEndsSetUp::StopEndsSetUp(const char* phase) : previous_(g_set_up_phase.exchange(phase, std::memory_order_acq_rel)) {
    if (const int sig = stop_signal()) {
        std::fflush(stdout);
        end_set_up(sig, phase);
    }
}

StopEndsSetUp::~StopEndsSetUp() { g_set_up_phase.store(previous_, std::memory_order_release); }

void reset_stop_request() { g_signal.store(0, std::memory_order_release); }

}  // namespace tridex::app
