// haptics/realtime.cpp - SCHED_FIFO and mlockall requests, refusals reported rather than thrown.
#include "haptics/realtime.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <time.h>

#include <algorithm>
#include <cerrno>
#include <fstream>
#include <sstream>
#include <string>

namespace tridex::haptics {

std::int64_t monotonic_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000LL + ts.tv_nsec;
}

void sleep_until_ns(std::int64_t t_ns) {
    timespec ts{};
    ts.tv_sec = static_cast<time_t>(t_ns / 1'000'000'000LL);
    ts.tv_nsec = static_cast<long>(t_ns % 1'000'000'000LL);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
}


RealtimeStatus request_realtime(int priority, bool lock_memory) {
    RealtimeStatus st;
    const int lo = sched_get_priority_min(SCHED_FIFO);
    const int hi = sched_get_priority_max(SCHED_FIFO);
    if (lo < 0 || hi < lo) {
        st.fifo_errno = EINVAL;
    } else {
        sched_param sp{};
        sp.sched_priority = std::clamp(priority, lo, hi);
        const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
        if (rc == 0) {
            // Confirm: some sandboxes report success without applying the policy.
            int policy = 0;
            sched_param now{};
            if (pthread_getschedparam(pthread_self(), &policy, &now) == 0 && policy == SCHED_FIFO) {
                st.fifo = true;
                st.priority = now.sched_priority;
            } else {
                st.fifo_errno = EPERM;
            }
        } else {
            st.fifo_errno = rc;
        }
    }
    if (lock_memory) {
        if (mlockall(MCL_CURRENT | MCL_ONFAULT) == 0) st.memory_locked = true;
        else st.lock_errno = errno;
    }
    return st;
}

namespace {

std::string first_line(const char* path) {
    std::ifstream f(path);
    std::string line;
    std::getline(f, line);
    return line;
}

}  // namespace

std::string kernel_preemption() {
    // "none voluntary (full) lazy": the mode in parentheses is active.
    const std::string dyn = first_line("/sys/kernel/debug/sched/preempt");
    if (const auto a = dyn.find('('), b = dyn.find(')'); a != std::string::npos && b != std::string::npos && b > a)
        return dyn.substr(a + 1, b - a - 1);
    std::istringstream cmdline(first_line("/proc/cmdline"));
    for (std::string arg; cmdline >> arg;)
        if (arg.rfind("preempt=", 0) == 0) return arg.substr(8);
    const std::string version = first_line("/proc/sys/kernel/version");
    if (version.find("PREEMPT_RT") != std::string::npos) return "rt";
    if (version.find("PREEMPT_DYNAMIC") != std::string::npos) return "dynamic (mode not readable)";
    if (version.find("PREEMPT_LAZY") != std::string::npos) return "lazy";
    if (version.find("PREEMPT ") != std::string::npos) return "full";
    return version.empty() ? "unknown" : "none";
}

}  // namespace tridex::haptics
