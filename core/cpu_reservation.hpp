// core/cpu_reservation.hpp - one CPU set aside for a real-time thread, and the threads kept off it.
#pragma once

namespace tridex {

/// Sets one CPU aside for the calling thread: pins it to the last CPU it may run on and moves every thread
/// that is kept off (KeepOffReservedCpu) to its other CPUs, now and for as long as the reservation lasts.
/// Why: on a kernel without full preemption a real-time thread whose timer fires while another task on its
/// core is inside a long system call (a software present's socket write of a whole frame, say) starts only
/// when that call ends; keeping such threads on other cores removes those late starts. Meant for a
/// SCHED_FIFO thread, which preempts ordinary work on its core whenever the kernel allows; an ordinary thread
/// pinned to one core would lose the other cores. Returns the CPU (0-based, as sched_getcpu numbers them),
/// or -1 when the calling thread may run on fewer than 2 CPUs, another thread holds the reservation, the
/// system refuses the affinity, or on systems other than Linux. Never throws.
int reserve_cpu_for_this_thread();

/// Ends the reservation the calling thread holds: gives it back the CPUs it had before and moves the kept-off
/// threads back to theirs. Does nothing when the calling thread holds none. Never throws.
void release_reserved_cpu();

/// The CPU reserve_cpu_for_this_thread() set aside, or -1 when none is. Never throws.
int reserved_cpu();

/// While alive, keeps the thread that made it off the reserved CPU: at once when one is reserved, or when one
/// is reserved later. Its destructor gives the thread back the CPUs it had. Threads this thread starts while it
/// is kept off inherit the narrower set, so make it after the long-lived worker threads are started. A thread
/// whose own CPUs are only the reserved one stays where it is. Not copyable; destroy it on the thread that made
/// it. Never throws.
class KeepOffReservedCpu {
public:
    KeepOffReservedCpu();
    ~KeepOffReservedCpu();
    KeepOffReservedCpu(const KeepOffReservedCpu&) = delete;
    KeepOffReservedCpu& operator=(const KeepOffReservedCpu&) = delete;

    /// True while the thread runs off a reserved CPU (one is reserved and the thread had another to go to).
    bool moved() const;

private:
    int tid_ = 0;
};

}  // namespace tridex
