// tests/app/test_stop_signal.cpp - SIGINT and SIGTERM during a session's set-up end the program at once, naming the
// phase; outside a set-up scope they only ask the session to end.
#include <gtest/gtest.h>

#include <csignal>

#include "app/support/stop_signal.hpp"

using namespace tridex::app;

TEST(StopSignal, ASignalDuringSetUpEndsTheProgramNamingThePhase) {
    EXPECT_EXIT(
        {
            install_stop_handlers();
            const StopEndsSetUp set_up("loading the workpiece");
            std::raise(SIGTERM);
            std::abort();  // not reached: the handler ends the process
        },
        testing::ExitedWithCode(128 + SIGTERM), "tridex: SIGTERM while loading the workpiece: nothing to keep, stopped");
    EXPECT_EXIT(
        {
            install_stop_handlers();
            const StopEndsSetUp outer("loading the workpiece");
            const StopEndsSetUp inner("contouring the workpiece");
            std::raise(SIGINT);
            std::abort();
        },
        testing::ExitedWithCode(128 + SIGINT), "SIGINT while contouring the workpiece");
}

TEST(StopSignal, ASignalBeforeSetUpEndsTheProgramWhenSetUpBegins) {
    EXPECT_EXIT(
        {
            install_stop_handlers();
            std::raise(SIGINT);  // recorded only: no set-up scope yet
            if (!stop_requested()) std::abort();
            const StopEndsSetUp set_up("loading the workpiece");
            std::abort();
        },
        testing::ExitedWithCode(128 + SIGINT), "SIGINT while loading the workpiece");
}

TEST(StopSignal, AfterSetUpASignalOnlyAsksTheSessionToEnd) {
    install_stop_handlers();
    reset_stop_request();
    { const StopEndsSetUp set_up("loading the workpiece"); }
    std::raise(SIGTERM);
    EXPECT_TRUE(stop_requested());
    EXPECT_STREQ(stop_signal_name(), "SIGTERM");
    reset_stop_request();
    std::signal(SIGTERM, SIG_DFL);
    std::signal(SIGINT, SIG_DFL);
}
