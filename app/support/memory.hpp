// app/support/memory.hpp - how much memory a model may take on this machine.
#pragma once

#include <cstddef>

namespace tridex::app {

/// Bytes the tri-dexel model may use: half of the physical memory currently available
/// (sysconf _SC_AVPHYS_PAGES), so the renderer, contouring and the OS keep the rest; 2 GiB when the
/// OS does not say.
std::size_t model_memory_budget_bytes();

/// Bytes of memory a new allocation can have now without swapping: /proc/meminfo's MemAvailable (free memory plus
/// the page cache the kernel can drop); sysconf _SC_AVPHYS_PAGES when that file is unreadable; 0 when neither says.
std::size_t available_memory_bytes();

}  // namespace tridex::app
