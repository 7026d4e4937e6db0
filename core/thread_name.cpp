// core/thread_name.cpp - pthread_setname_np on Linux.
#include "core/thread_name.hpp"

#ifdef __linux__
#include <pthread.h>
#endif

namespace tridex {

void name_this_thread(const std::string& name) {
#ifdef __linux__
    const std::string cut = name.substr(0, 15);  // the kernel's limit (16 bytes with the terminator)
    pthread_setname_np(pthread_self(), cut.c_str());
#else
    (void)name;
#endif
}

}  // namespace tridex
