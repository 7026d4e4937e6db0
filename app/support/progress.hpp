// app/support/progress.hpp - what the program shows while a long step runs: a bar redrawn in place on a terminal,
// one line per step otherwise (docs/commands/index.md, "Progress of long steps").
#pragma once

#include <condition_variable>
#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "core/progress.hpp"

namespace tridex::app {

/// Where a ProgressReporter writes, and the clock it reads (a test gives a fake of each).
struct ProgressOutput {
    std::function<void(std::string_view)> write;  ///< appends text to the output; must not throw
    bool terminal = false;                        ///< the output is a terminal: a bar redrawn in place
    std::function<double()> now_s;                ///< a monotonic clock, s
    int columns = 80;                             ///< the terminal's width, characters (a bar line is cut to fit)
    /// On a terminal: a thread of the reporter's own redraws the bar every kRedrawS while a step runs, so that a step
    /// whose work tells no fraction (or seldom) still shows its time. false: drawn only on updates (tests).
    bool ticker = false;
};

/// Shows the long steps of a command. On a terminal: one line with the step's name, a bar, the percentage and the
/// time since the step began, redrawn in place (carriage return) at most every kRedrawS, replaced at the step's end
/// by "NAME: T s". Elsewhere (a pipe, a file, a CI log): no bar, only the line "NAME: T s" when the step ends. A step
/// that ends within kQuietS prints nothing at all (its bar, if drawn, is erased), so quick commands stay quiet. Steps
/// nest (a benchmark's step around the scan conversion it does): the innermost running step has the bar, each prints
/// its own line when it ends, and the outer step's bar comes back after. Steps end innermost first (RAII).
/// Thread-safe (one mutex); a step's updates come from the thread that runs its work (core/progress.hpp).
class ProgressReporter {
public:
    /// A bar is redrawn at most this often, s.
    static constexpr double kRedrawS = 0.1;
    /// A step shorter than this prints nothing, s.
    static constexpr double kQuietS = 1.0;

    /// Reports to `out`; out.write and out.now_s must be set.
    explicit ProgressReporter(ProgressOutput out);
    /// Stops the ticker thread, if any (a step still running shows nothing more).
    ~ProgressReporter();
    ProgressReporter(const ProgressReporter&) = delete;
    ProgressReporter& operator=(const ProgressReporter&) = delete;

    /// One step, shown from construction to destruction (move-only). Its updates are fractions 0..1; a step that
    /// never gets one shows its elapsed time only.
    class Step {
    public:
        Step(Step&& other) noexcept;
        Step& operator=(Step&&) = delete;
        Step(const Step&) = delete;
        Step& operator=(const Step&) = delete;
        /// Ends the step (ProgressReporter's end line).
        ~Step();
        /// The fraction done, 0..1 (clamped); redraws the bar when kRedrawS passed since the last draw.
        void update(double fraction);
        /// update() as a core ProgressFn, for compute code: valid until the step ends (empty once it has).
        ProgressFn fn();
        /// Ends the step now (the destructor then does nothing); returns its duration, s.
        double finish();

    private:
        friend class ProgressReporter;
        Step(ProgressReporter* owner, std::size_t depth);
        ProgressReporter* owner_;
        std::size_t depth_;  // its place in the reporter's stack of running steps
        bool shown_;         // false: finished (or moved from)
    };

    /// Begins a step named `name` (a short phrase: "scan-converting bunny.off at 2048 cells").
    Step step(std::string name);

private:
    // A running step: its name, when it began (s, out.now_s) and its fraction (< 0: none told yet).
    struct Frame {
        std::string name;
        double begin_s = 0.0;
        double fraction = -1.0;
    };
    void update(std::size_t depth, double fraction);
    double end(std::size_t depth);
    void draw(double now);  // the innermost step's bar; mutex_ held
    void tick_loop();

    ProgressOutput out_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::thread ticker_;
    bool stopping_ = false;
    std::vector<Frame> stack_;  // the running steps, outermost first
    double last_draw_s_ = 0.0;
    bool drawn_ = false;  // a bar is on the terminal's line
};

/// The program's reporter, on the steady clock: when stderr is a terminal (isatty(2)), the bar on stderr (as wide as
/// the terminal); otherwise the step lines on stdout, with the command's other messages, so that stderr keeps to errors.
ProgressReporter& progress();

}  // namespace tridex::app
