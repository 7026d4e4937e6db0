// gpu/driver_threads.hpp - finding the worker threads a CPU Vulkan driver starts, and spreading them over cores.
#pragma once

#include <span>
#include <string>
#include <vector>

namespace tridex::gpu {

/// One thread of this process: its kernel thread id and its name (Linux `comm`, at most 15 characters).
struct ProcessThread {
    int tid = 0;
    std::string name;
};

/// The threads of this process now, sorted by thread id (Linux: /proc/self/task). Empty on other systems
/// or when /proc is not readable; threads that end while being listed are left out. Never throws.
std::vector<ProcessThread> process_threads();

/// The threads in `after` whose id is not in `before` (both sorted by id, as process_threads() returns
/// them) and whose name is `unnamed` (a thread that was never named keeps the name of the thread that
/// started it) or begins with "llvmpipe-" (Mesa llvmpipe's rasteriser threads). These are the worker
/// threads a driver started between the two listings; threads named otherwise (e.g. Mesa's "disk$0"
/// shader-cache thread, or tridex's own "tridex-..." threads, core/thread_name.hpp) are not workers.
/// Returns them sorted by id.
std::vector<ProcessThread> new_worker_threads(std::span<const ProcessThread> before, std::span<const ProcessThread> after,
                                              const std::string& unnamed);

/// Gives each thread in `threads` one CPU of those the calling thread may run on, in turn (thread i gets
/// the (i mod n)-th allowed CPU), so that the threads of one pool run on different cores. Why: Mesa
/// llvmpipe (lavapipe) wakes all its compute threads at once for each dispatch, and Linux often queues two
/// of them on the waker's core while another core idles; pinned, lavapipe's sweep dispatches ran about
/// 1.6x faster on a 2-core machine (compute/gpu/gpu_sculptor.cpp; numbers in the README). Returns how many
/// threads were pinned: 0 when fewer than 2 CPUs are allowed, on systems other than Linux, or for threads
/// that have ended. Never throws.
int spread_over_cpus(std::span<const ProcessThread> threads);

/// The calling thread's name (Linux `comm`); empty when unknown. Never throws.
std::string current_thread_name();

}  // namespace tridex::gpu
