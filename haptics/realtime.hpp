// haptics/realtime.hpp - ask the OS for real-time scheduling and resident memory for the haptic thread.
#pragma once

#include <cstdint>
#include <string>

namespace tridex::haptics {

/// CLOCK_MONOTONIC now, in whole nanoseconds: the clock the real-time threads' absolute deadlines are on
/// (std::chrono::steady_clock's on Linux). Never fails.
std::int64_t monotonic_ns();

/// Sleeps until CLOCK_MONOTONIC reaches `t_ns` (an absolute deadline, ns: clock_nanosleep with TIMER_ABSTIME), going
/// back to sleep after a signal; returns at once for a deadline already past.
void sleep_until_ns(std::int64_t t_ns);

/// What the system granted to request_realtime(). Refusals are normal (an unprivileged user, a
/// container without CAP_SYS_NICE, an RT-throttled cgroup) and only reported.
struct RealtimeStatus {
    bool fifo = false;           ///< the calling thread now runs under SCHED_FIFO at `priority`
    int priority = 0;            ///< the SCHED_FIFO priority granted (0 when refused)
    int fifo_errno = 0;          ///< pthread_setschedparam's error when refused (EPERM, EINVAL, ...), else 0
    bool memory_locked = false;  ///< mlockall succeeded: pages already mapped stay resident once touched
    int lock_errno = 0;          ///< mlockall's errno when refused (EPERM, ENOMEM, ...), else 0
};

/// Asks for SCHED_FIFO at `priority` for the calling thread (pthread_setschedparam; the priority is
/// clamped to the system's SCHED_FIFO range) and, when lock_memory is true, for
/// mlockall(MCL_CURRENT | MCL_ONFAULT) (process-wide; it stays in force after the loop stops): every
/// page of the process mapped now is locked as soon as it is touched, so
/// the haptic loop's preallocated records, its stack and the snapshots it reads cannot be paged out.
/// MCL_ONFAULT keeps large reserved-but-untouched mappings (the model's memory budget) from being
/// populated; MCL_FUTURE is not used because under a small RLIMIT_MEMLOCK it would make later
/// allocations of other threads fail. Never throws and never aborts: refusals are returned.
/// Linux only (sched(7), mlock(2)).
RealtimeStatus request_realtime(int priority, bool lock_memory);

/// The running kernel's preemption model, which bounds how late a SCHED_FIFO thread can start after its timer:
/// under "none" or "voluntary" it waits until the task on its core leaves a kernel section (file-system writeback,
/// a large socket write), which can take milliseconds. Read from /sys/kernel/debug/sched/preempt (the active mode of
/// a PREEMPT_DYNAMIC kernel, needs debugfs), else a preempt= boot argument (/proc/cmdline), else the build named in
/// /proc/sys/kernel/version: "full", "voluntary", "none", "lazy", "rt", or "dynamic (mode not readable)" / "unknown".
/// Never throws. Linux only.
std::string kernel_preemption();

}  // namespace tridex::haptics
