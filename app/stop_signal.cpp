// app/stop_signal.cpp - the SIGINT / SIGTERM flag.
#include "app/stop_signal.hpp"

#include <atomic>
#include <csignal>

namespace tridex::app {

namespace {

std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal flag must be lock-free to be set from a handler");

extern "C" void on_stop_signal(int sig) {
    int expected = 0;
    if (!g_signal.compare_exchange_strong(expected, sig)) {
        // A second signal: the default action (terminate) at once.
        std::signal(sig, SIG_DFL);
        std::raise(sig);
    }
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
