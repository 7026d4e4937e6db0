// gpu/driver_threads.cpp - /proc/self/task listings and sched_setaffinity, on Linux; nothing elsewhere.
#include "gpu/driver_threads.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>

#ifdef __linux__
#include <sched.h>
#endif

namespace tridex::gpu {
namespace {

std::string read_name(const std::filesystem::path& comm) {
    std::ifstream in(comm);
    std::string name;
    if (!in || !std::getline(in, name)) return {};
    return name;
}

}  // namespace

std::vector<ProcessThread> process_threads() {
    std::vector<ProcessThread> out;
#ifdef __linux__
    std::error_code ec;
    for (std::filesystem::directory_iterator it("/proc/self/task", ec), end; !ec && it != end; it.increment(ec)) {
        const std::string id = it->path().filename().string();
        if (id.empty() || !std::all_of(id.begin(), id.end(), [](char c) { return c >= '0' && c <= '9'; })) continue;
        std::string name = read_name(it->path() / "comm");
        if (name.empty()) continue;  // ended while listed
        out.push_back(ProcessThread{std::stoi(id), std::move(name)});
    }
    std::sort(out.begin(), out.end(), [](const ProcessThread& a, const ProcessThread& b) { return a.tid < b.tid; });
#endif
    return out;
}

std::vector<ProcessThread> new_worker_threads(std::span<const ProcessThread> before, std::span<const ProcessThread> after,
                                              const std::string& unnamed) {
    std::vector<ProcessThread> out;
    for (const ProcessThread& t : after) {
        const bool old = std::binary_search(before.begin(), before.end(), t,
                                            [](const ProcessThread& a, const ProcessThread& b) { return a.tid < b.tid; });
        if (old) continue;
        if ((!unnamed.empty() && t.name == unnamed) || t.name.rfind("llvmpipe-", 0) == 0) out.push_back(t);
    }
    return out;
}

int spread_over_cpus(std::span<const ProcessThread> threads) {
#ifdef __linux__
    cpu_set_t allowed;
    CPU_ZERO(&allowed);
    if (sched_getaffinity(0, sizeof allowed, &allowed) != 0) return 0;
    std::vector<int> cpus;
    for (int c = 0; c < CPU_SETSIZE; ++c)
        if (CPU_ISSET(c, &allowed)) cpus.push_back(c);
    if (cpus.size() < 2) return 0;
    int pinned = 0;
    for (std::size_t i = 0; i < threads.size(); ++i) {
        cpu_set_t one;
        CPU_ZERO(&one);
        CPU_SET(cpus[i % cpus.size()], &one);
        if (sched_setaffinity(threads[i].tid, sizeof one, &one) == 0) ++pinned;
    }
    return pinned;
#else
    (void)threads;
    return 0;
#endif
}

std::string current_thread_name() {
#ifdef __linux__
    return read_name("/proc/thread-self/comm");
#else
    return {};
#endif
}

}  // namespace tridex::gpu
