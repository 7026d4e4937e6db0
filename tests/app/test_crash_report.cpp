// tests/app/test_crash_report.cpp - what a crash writes before the program dies.
#include "app/support/crash_report.hpp"

#include <gtest/gtest.h>
#include <pthread.h>
#include <unistd.h>

#include <csignal>
#include <cstdint>
#include <string>
#include <thread>

namespace {

using tridex::app::install_crash_report;
using tridex::app::set_crash_note;
using tridex::app::write_crash_report;

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

/// What write_crash_report writes for `signal` and `address`, read back through a pipe.
std::string report_of(int signal, const void* address) {
    int fds[2];
    EXPECT_EQ(pipe(fds), 0);
    write_crash_report(fds[1], signal, address);
    close(fds[1]);
    std::string out;
    char buf[4096];
    for (ssize_t n; (n = read(fds[0], buf, sizeof buf)) > 0;) out.append(buf, static_cast<std::size_t>(n));
    close(fds[0]);
    return out;
}

}  // namespace

// The report names the signal, the faulting address, the thread and the note, then lists the call stack.
TEST(CrashReport, NamesSignalAddressThreadAndNote) {
    set_crash_note("the session's journal is out/run/session.tdj");
    std::string report;
    std::thread([&] {
        pthread_setname_np(pthread_self(), "tridex-probe");
        report = report_of(SIGSEGV, reinterpret_cast<const void*>(std::uintptr_t{0x7fa900000010}));
    }).join();
    EXPECT_NE(report.find("tridex: crashed: SIGSEGV at address 0x7fa900000010 on thread tridex-probe\n"),
              std::string::npos)
        << report;
    EXPECT_NE(report.find("\ntridex: the session's journal is out/run/session.tdj\n"), std::string::npos) << report;
    const auto stack = report.find("tridex: call stack");
    ASSERT_NE(stack, std::string::npos) << report;
    EXPECT_GT(report.size(), stack + 100) << "no frames after the call stack's heading: " << report;
    // No address for a signal sent rather than raised by a fault; no note line once the note is cleared.
    set_crash_note("");
    const std::string abort_report = report_of(SIGABRT, nullptr);
    EXPECT_EQ(abort_report.rfind("tridex: crashed: SIGABRT", 0), 0u) << abort_report;
    EXPECT_EQ(abort_report.find(" at address "), std::string::npos) << abort_report;
    EXPECT_EQ(abort_report.find("journal"), std::string::npos) << abort_report;
    // A note longer than the kept 1023 bytes is cut, not overrun.
    set_crash_note(std::string(5000, 'x'));
    const std::string long_report = report_of(SIGBUS, nullptr);
    EXPECT_NE(long_report.find("tridex: " + std::string(1023, 'x') + "\n"), std::string::npos);
    set_crash_note("");
}

// Installed, a real fault is reported, and the program still dies of the signal (exit status, core dump).
TEST(CrashReportDeathTest, AFaultIsReportedThenKillsTheProgram) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    EXPECT_EQ(install_crash_report(), !kSanitized) << "installed in a sanitizer build, or refused in a plain one";
    if (kSanitized) return;  // the sanitizer's own handler reports faults there
    EXPECT_EXIT(
        {
            set_crash_note("recover with: tridex recover out/run/session.tdj");
            volatile std::uintptr_t where = 0x10;
            *reinterpret_cast<volatile int*>(where) = 1;
        },
        testing::KilledBySignal(SIGSEGV),
        "tridex: crashed: SIGSEGV at address 0x10 on thread [^\n]+\ntridex: recover with: tridex recover "
        "out/run/session.tdj\ntridex: call stack");
    EXPECT_EXIT(std::abort(), testing::KilledBySignal(SIGABRT), "tridex: crashed: SIGABRT on thread");
}
