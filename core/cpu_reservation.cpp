// core/cpu_reservation.cpp - sched_setaffinity on Linux (thread ids from gettid); nothing elsewhere.
#include "core/cpu_reservation.hpp"

#include <map>
#include <mutex>

#ifdef __linux__
#include <sched.h>
#include <unistd.h>
#endif

namespace tridex {

#ifdef __linux__

namespace {

/// A thread kept off the reserved CPU: the CPUs it may run on when nothing is reserved, and whether it runs off the
/// reserved one now.
struct KeptOff {
    cpu_set_t had{};
    bool moved = false;
};

/// The process-wide state: who holds the reservation, and the threads kept off it.
struct Reservation {
    std::mutex mutex;
    int cpu = -1;
    int owner = 0;
    cpu_set_t owner_had{};
    std::map<int, KeptOff> kept_off;  ///< by thread id
};

Reservation& state() {
    static Reservation r;
    return r;
}

int this_tid() { return static_cast<int>(gettid()); }

/// `had` without `cpu`, applied to `tid`; false when nothing would be left or the system refuses.
bool move_off(int tid, const cpu_set_t& had, int cpu) {
    cpu_set_t narrower = had;
    CPU_CLR(cpu, &narrower);
    if (CPU_COUNT(&narrower) == 0) return false;
    return sched_setaffinity(tid, sizeof narrower, &narrower) == 0;
}

/// The highest-numbered CPU in `set`, or -1 when it is empty.
int last_cpu(const cpu_set_t& set) {
    for (int c = CPU_SETSIZE - 1; c >= 0; --c)
        if (CPU_ISSET(c, &set)) return c;
    return -1;
}

}  // namespace

int reserve_cpu_for_this_thread() {
    Reservation& r = state();
    const std::lock_guard<std::mutex> lock(r.mutex);
    if (r.cpu >= 0) return -1;
    cpu_set_t had;
    CPU_ZERO(&had);
    if (sched_getaffinity(0, sizeof had, &had) != 0 || CPU_COUNT(&had) < 2) return -1;
    const int cpu = last_cpu(had);
    cpu_set_t only;
    CPU_ZERO(&only);
    CPU_SET(cpu, &only);
    if (sched_setaffinity(0, sizeof only, &only) != 0) return -1;
    r.cpu = cpu;
    r.owner = this_tid();
    r.owner_had = had;
    for (auto& [tid, k] : r.kept_off) k.moved = move_off(tid, k.had, cpu);
    return cpu;
}

void release_reserved_cpu() {
    Reservation& r = state();
    const std::lock_guard<std::mutex> lock(r.mutex);
    if (r.cpu < 0 || r.owner != this_tid()) return;
    sched_setaffinity(0, sizeof r.owner_had, &r.owner_had);
    for (auto& [tid, k] : r.kept_off) {
        if (k.moved) sched_setaffinity(tid, sizeof k.had, &k.had);
        k.moved = false;
    }
    r.cpu = -1;
    r.owner = 0;
}

int reserved_cpu() {
    Reservation& r = state();
    const std::lock_guard<std::mutex> lock(r.mutex);
    return r.cpu;
}

KeepOffReservedCpu::KeepOffReservedCpu() : tid_(this_tid()) {
    Reservation& r = state();
    const std::lock_guard<std::mutex> lock(r.mutex);
    cpu_set_t had;
    CPU_ZERO(&had);
    if (sched_getaffinity(0, sizeof had, &had) != 0) {
        tid_ = 0;
        return;
    }
    r.kept_off[tid_] = KeptOff{had, r.cpu >= 0 && move_off(tid_, had, r.cpu)};
}

KeepOffReservedCpu::~KeepOffReservedCpu() {
    if (tid_ == 0) return;
    Reservation& r = state();
    const std::lock_guard<std::mutex> lock(r.mutex);
    const auto it = r.kept_off.find(tid_);
    if (it == r.kept_off.end()) return;
    if (it->second.moved) sched_setaffinity(tid_, sizeof it->second.had, &it->second.had);
    r.kept_off.erase(it);
}

bool KeepOffReservedCpu::moved() const {
    if (tid_ == 0) return false;
    Reservation& r = state();
    const std::lock_guard<std::mutex> lock(r.mutex);
    const auto it = r.kept_off.find(tid_);
    return it != r.kept_off.end() && it->second.moved;
}

#else

int reserve_cpu_for_this_thread() { return -1; }
void release_reserved_cpu() {}
int reserved_cpu() { return -1; }
KeepOffReservedCpu::KeepOffReservedCpu() = default;
KeepOffReservedCpu::~KeepOffReservedCpu() = default;
bool KeepOffReservedCpu::moved() const { return false; }

#endif

}  // namespace tridex
