// app/support/crash_report.hpp - what a crash says before the program dies: the signal, the thread, where the
// session's journal is, and the call stack.
#pragma once

#include <string>

namespace tridex::app {

/// Installs handlers for SIGSEGV, SIGBUS, SIGFPE, SIGILL and SIGABRT that write to stderr, before the program dies
/// with the signal's default action (and a core dump where the system keeps them):
///   tridex: crashed: SIGSEGV at address 0x7fa900000010 on thread tridex-lod
///   tridex: <the note of set_crash_note(), e.g. where the session's journal is and how to recover the model>
///   tridex: call stack (addresses: addr2line -f -C -e <the tridex binary> ADDRESS):
///   <one frame per line>
/// Only async-signal-safe calls run in the handler, apart from glibc's backtrace(), which is loaded here so that it
/// needs no allocation then. Not installed in sanitizer builds (ASan, TSan), whose own reports say more. Returns
/// true when installed; idempotent; never throws.
bool install_crash_report();

/// Sets the line a crash report adds after the signal's (at most 1023 bytes kept; "" = none), e.g. the session's
/// journal and the command that rebuilds its model. Thread-safe; the handler reads the newest complete note.
void set_crash_note(const std::string& note);

/// Writes the crash report for `signal` (a faulting `address`, or nullptr) to file descriptor `fd`, as the handler
/// does: for tests. Never throws.
void write_crash_report(int fd, int signal, const void* address);

}  // namespace tridex::app
