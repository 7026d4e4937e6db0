// app/stop_signal.cpp - the SIGINT / SIGTERM flag.
#include "app/stop_signal.hpp"

#include <atomic>
#include <csignal>
#include <ctime>

namespace tridex::app {

namespace {

std::atomic<int> g_signal{0};
std::atomic<long long> g_first_ns{0};  // CLOCK_MONOTONIC time of the first signal
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

extern "C" void on_stop_signal(int sig) {
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

void reset_stop_request() { g_signal.store(0, std::memory_order_release); }

}  // namespace tridex::app
