// app/support/memory.cpp - the model memory budget from the OS.
#include "app/support/memory.hpp"

#include <unistd.h>

#include <fstream>
#include <string>

namespace tridex::app {

std::size_t model_memory_budget_bytes() {
    const long pages = sysconf(_SC_AVPHYS_PAGES);
    const long page = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page <= 0) return std::size_t(1) << 31;  // unknown: assume 2 GiB
    return static_cast<std::size_t>(pages) * static_cast<std::size_t>(page) / 2;
}

std::size_t available_memory_bytes() {
    std::ifstream in("/proc/meminfo");
    std::string key;
    unsigned long long kib = 0;
    std::string unit;
    while (in >> key >> kib >> unit)
        if (key == "MemAvailable:") return static_cast<std::size_t>(kib) * 1024u;
    const long pages = sysconf(_SC_AVPHYS_PAGES);
    const long page = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page <= 0) return 0;
    return static_cast<std::size_t>(pages) * static_cast<std::size_t>(page);
}

}  // namespace tridex::app
