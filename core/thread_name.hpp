// core/thread_name.hpp - naming the calling thread (what top, perf and /proc show).
#pragma once

#include <string>

namespace tridex {

/// Names the calling thread `name` (Linux: pthread_setname_np; the kernel keeps at most 15 bytes, so a
/// longer name is cut to its first 15). tridex names its own threads "tridex-haptics", "tridex-sculpt",
/// "tridex-sweep", "tridex-lod" and the task pool's workers "tridex-pool", so that profilers tell them apart and
/// gpu::Context does not take them for a Vulkan driver's workers (gpu/driver_threads.hpp). Does nothing on other systems; never throws.
void name_this_thread(const std::string& name);

}  // namespace tridex
