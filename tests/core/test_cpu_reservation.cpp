// tests/core/test_cpu_reservation.cpp - a CPU set aside for one thread, and the threads kept off it.
#include "core/cpu_reservation.hpp"

#include <gtest/gtest.h>
#include <sched.h>
#include <unistd.h>

#include <atomic>
#include <functional>
#include <latch>
#include <thread>

namespace {

using tridex::KeepOffReservedCpu;
using tridex::release_reserved_cpu;
using tridex::reserve_cpu_for_this_thread;
using tridex::reserved_cpu;

cpu_set_t affinity_of(int tid) {
    cpu_set_t set;
    CPU_ZERO(&set);
    EXPECT_EQ(sched_getaffinity(tid, sizeof set, &set), 0);
    return set;
}

int highest(const cpu_set_t& set) {
    for (int c = CPU_SETSIZE - 1; c >= 0; --c)
        if (CPU_ISSET(c, &set)) return c;
    return -1;
}

/// Runs `body` on a new thread and waits for it.
void on_thread(const std::function<void()>& body) { std::thread(body).join(); }

}  // namespace

// The reserving thread runs on its last CPU alone; threads kept off, before or after the reservation, run on the
// others; the release gives every thread back its CPUs. On a one-CPU machine nothing can be set aside.
TEST(CpuReservation, SetsTheLastCpuAsideAndKeepsOthersOff) {
    const cpu_set_t all = affinity_of(0);
    const int cpus = CPU_COUNT(&all);
    const int last = highest(all);
    std::latch kept_before(1), reserved(1), seen_moved(1), checked(1), released(1);
    std::atomic<int> tid_before{0};
    std::thread before([&] {
        tid_before = static_cast<int>(gettid());
        const KeepOffReservedCpu off;
        EXPECT_FALSE(off.moved()) << "moved before anything was reserved";
        kept_before.count_down();
        reserved.wait();
        EXPECT_EQ(off.moved(), cpus >= 2);
        seen_moved.count_down();
        checked.wait();
        released.wait();
        EXPECT_FALSE(off.moved()) << "still kept off after the release";
        const cpu_set_t restored = affinity_of(0);
        EXPECT_TRUE(CPU_EQUAL(&restored, &all)) << "the kept-off thread did not get its CPUs back";
    });
    kept_before.wait();
    std::thread owner([&] {
        const int cpu = reserve_cpu_for_this_thread();
        if (cpus < 2) {
            EXPECT_EQ(cpu, -1);
            reserved.count_down();
            checked.wait();
            released.count_down();
            return;
        }
        EXPECT_EQ(cpu, last);
        EXPECT_EQ(reserved_cpu(), last);
        const cpu_set_t mine = affinity_of(0);
        EXPECT_EQ(CPU_COUNT(&mine), 1);
        EXPECT_TRUE(CPU_ISSET(last, &mine));
        reserved.count_down();
        checked.wait();
        EXPECT_EQ(reserve_cpu_for_this_thread(), -1) << "a second reservation while one is held";
        release_reserved_cpu();
        EXPECT_EQ(reserved_cpu(), -1);
        const cpu_set_t back = affinity_of(0);
        EXPECT_TRUE(CPU_EQUAL(&back, &all)) << "the owner did not get its CPUs back";
        released.count_down();
    });
    reserved.wait();
    if (cpus >= 2) {
        const cpu_set_t kept = affinity_of(tid_before);
        EXPECT_FALSE(CPU_ISSET(last, &kept)) << "a thread kept off before the reservation runs on the reserved CPU";
        EXPECT_EQ(CPU_COUNT(&kept), cpus - 1);
        on_thread([&] {  // kept off after the reservation: moved at once, and back when it ends
            {
                const KeepOffReservedCpu off;
                EXPECT_TRUE(off.moved());
                const cpu_set_t now = affinity_of(0);
                EXPECT_FALSE(CPU_ISSET(last, &now));
            }
            const cpu_set_t after = affinity_of(0);
            EXPECT_TRUE(CPU_EQUAL(&after, &all)) << "the guard's end did not give the CPUs back";
        });
        on_thread([&] {  // not the owner: its release changes nothing
            release_reserved_cpu();
            EXPECT_EQ(reserved_cpu(), last);
        });
    }
    seen_moved.wait();  // the release must not come before the kept-off thread has looked
    checked.count_down();
    before.join();
    owner.join();
}

// A thread that may run on one CPU only cannot set it aside, and a kept-off thread whose only CPU is the reserved
// one stays there.
TEST(CpuReservation, OneCpuIsNeverSetAsideOrLeft) {
    const cpu_set_t all = affinity_of(0);
    const int last = highest(all);
    on_thread([&] {
        cpu_set_t one;
        CPU_ZERO(&one);
        CPU_SET(last, &one);
        ASSERT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
        EXPECT_EQ(reserve_cpu_for_this_thread(), -1);
        EXPECT_EQ(reserved_cpu(), -1);
        const cpu_set_t now = affinity_of(0);
        EXPECT_TRUE(CPU_EQUAL(&now, &one));
    });
    if (CPU_COUNT(&all) < 2) return;  // the other half needs a CPU to set aside
    std::latch kept(1), reserved(1), finished(1);
    std::thread only_last([&] {
        cpu_set_t one;
        CPU_ZERO(&one);
        CPU_SET(last, &one);
        EXPECT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
        const KeepOffReservedCpu off;
        kept.count_down();
        reserved.wait();
        EXPECT_FALSE(off.moved()) << "a thread with only the reserved CPU was moved";
        const cpu_set_t now = affinity_of(0);
        EXPECT_TRUE(CPU_EQUAL(&now, &one));
        finished.wait();
    });
    kept.wait();
    std::thread owner([&] {
        EXPECT_EQ(reserve_cpu_for_this_thread(), last);
        reserved.count_down();
        finished.wait();
        release_reserved_cpu();
    });
    reserved.wait();
    finished.count_down();
    only_last.join();
    owner.join();
    EXPECT_EQ(reserved_cpu(), -1);
}
