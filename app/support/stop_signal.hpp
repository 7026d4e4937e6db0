// app/support/stop_signal.hpp - SIGINT and SIGTERM end a session cleanly: the session loops poll a flag, stop their threads
// (zero force to the device), write their outputs, and the program exits 128 + the signal number.
#pragma once

namespace tridex::app {

/// Installs handlers for SIGINT and SIGTERM that only record the signal (async-signal-safe). The first signal asks
/// the running session to end; another one of either kind a second or more later ends the program at once with the
/// default action (as a user pressing Ctrl+C twice expects; one sooner is taken as the same event delivered twice,
/// as `timeout` does to its child and the child's process group). Idempotent.
void install_stop_handlers();

/// True once SIGINT or SIGTERM arrived (any thread; lock-free).
bool stop_requested();

/// The signal that asked the session to end (SIGINT = 2, SIGTERM = 15), or 0.
int stop_signal();

/// "SIGINT" or "SIGTERM" for stop_signal(), "" when none arrived.
const char* stop_signal_name();

/// While one is alive, SIGINT or SIGTERM ends the program at once with exit status 128 + the signal number, after
/// one line on stderr naming the phase ("tridex: SIGTERM while loading the workpiece: nothing to keep, stopped"):
/// for a session's set-up (reading files, scan conversion, the first contouring), which has no work to keep and
/// cannot poll stop_requested(). A signal that arrived before the scope began ends the program when it begins.
/// Scopes nest (the innermost phase is named); `phase` must outlive the scope (a string literal).
class StopEndsSetUp {
public:
    explicit StopEndsSetUp(const char* phase);
    ~StopEndsSetUp();
    StopEndsSetUp(const StopEndsSetUp&) = delete;
    StopEndsSetUp& operator=(const StopEndsSetUp&) = delete;

private:
    const char* previous_;
};

/// Forgets a received signal (tests).
void reset_stop_request();

}  // namespace tridex::app
