// app/support/progress.cpp - the progress bar on a terminal, one line per step elsewhere (progress.hpp).
#include "app/support/progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <utility>

namespace tridex::app {

namespace {

constexpr int kBarCells = 24;

std::string seconds_text(double s) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f s", s);
    return buf;
}

}  // namespace

ProgressReporter::ProgressReporter(ProgressOutput out) : out_(std::move(out)) {
    if (out_.terminal && out_.ticker) ticker_ = std::thread([this] { tick_loop(); });
}

ProgressReporter::~ProgressReporter() {
    {
        const std::lock_guard<std::mutex> hold(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    if (ticker_.joinable()) ticker_.join();
}

void ProgressReporter::tick_loop() {
    std::unique_lock<std::mutex> hold(mutex_);
    while (!stopping_) {
        wake_.wait_for(hold, std::chrono::duration<double>(kRedrawS));
        if (stopping_ || stack_.empty()) continue;
        const double now = out_.now_s();
        if (now - last_draw_s_ >= kRedrawS) draw(now);
    }
}

ProgressReporter::Step::Step(ProgressReporter* owner, std::size_t depth) : owner_(owner), depth_(depth), shown_(true) {}

ProgressReporter::Step::Step(Step&& other) noexcept
    : owner_(other.owner_), depth_(other.depth_), shown_(std::exchange(other.shown_, false)) {}

ProgressReporter::Step::~Step() { finish(); }

void ProgressReporter::Step::update(double fraction) {
    if (shown_) owner_->update(depth_, fraction);
}

ProgressFn ProgressReporter::Step::fn() {
    if (!shown_) return {};
    return [owner = owner_, depth = depth_](double fraction) { owner->update(depth, fraction); };
}

double ProgressReporter::Step::finish() {
    if (!shown_) return 0.0;
    shown_ = false;
    return owner_->end(depth_);
}

ProgressReporter::Step ProgressReporter::step(std::string name) {
    const std::lock_guard<std::mutex> hold(mutex_);
    const double now = out_.now_s();
    stack_.push_back(Frame{std::move(name), now, -1.0});
    last_draw_s_ = now;  // the new step's bar after kRedrawS: a quick one never shows
    return Step(this, stack_.size() - 1);
}

void ProgressReporter::update(std::size_t depth, double fraction) {
    const std::lock_guard<std::mutex> hold(mutex_);
    if (depth >= stack_.size()) return;
    stack_[depth].fraction = std::clamp(fraction, 0.0, 1.0);
    if (!out_.terminal || depth + 1 != stack_.size()) return;
    const double now = out_.now_s();
    if (now - last_draw_s_ < kRedrawS) return;
    draw(now);
}

void ProgressReporter::draw(double now) {
    const Frame& f = stack_.back();
    last_draw_s_ = now;
    drawn_ = true;
    std::string tail;  // the bar, the percentage and the time: kept whole; the name gives way to fit the width
    if (f.fraction >= 0.0) {
        const int filled = static_cast<int>(std::floor(f.fraction * kBarCells));
        tail += "[" + std::string(static_cast<std::size_t>(filled), '#') +
                std::string(static_cast<std::size_t>(kBarCells - filled), '.') + "] ";
        char pct[16];
        std::snprintf(pct, sizeof pct, "%3d%% ", static_cast<int>(std::floor(f.fraction * 100.0)));
        tail += pct;
    }
    tail += seconds_text(now - f.begin_s);
    const std::size_t room = static_cast<std::size_t>(std::max(out_.columns - 1, 8));
    std::string name = f.name;
    const std::size_t name_room = room > tail.size() + 1 ? room - tail.size() - 1 : 0;
    if (name.size() > name_room) name = name_room > 3 ? name.substr(0, name_room - 3) + "..." : "";
    std::string line = name.empty() ? tail : name + " " + tail;
    if (line.size() > room) line.resize(room);
    out_.write("\r" + line + "\x1b[K");
}

double ProgressReporter::end(std::size_t depth) {
    const std::lock_guard<std::mutex> hold(mutex_);
    if (depth >= stack_.size()) return 0.0;
    const double took = out_.now_s() - stack_[depth].begin_s;
    const std::string line = took < kQuietS ? "" : stack_[depth].name + ": " + seconds_text(took) + "\n";
    stack_.resize(depth);  // this step, and any begun inside it that was not ended (steps end innermost first)
    const std::string erase = out_.terminal && drawn_ ? "\r\x1b[K" : "";
    drawn_ = false;
    if (!erase.empty() || !line.empty()) out_.write(erase + line);
    return took;
}

ProgressReporter& progress() {
    static ProgressReporter reporter([] {
        ProgressOutput o;
        o.terminal = isatty(STDERR_FILENO) == 1;
        // The bar on the terminal's stderr; elsewhere the step lines join the command's other messages on stdout, so
        // that stderr keeps to errors (one line when a command fails, docs/commands/index.md).
        FILE* const stream = o.terminal ? stderr : stdout;
        o.write = [stream](std::string_view text) {
            std::fwrite(text.data(), 1, text.size(), stream);
            std::fflush(stream);
        };
        winsize ws{};
        if (o.terminal && ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0) o.columns = ws.ws_col;
        o.now_s = [] {
            return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
        };
        o.ticker = true;
        return o;
    }());
    return reporter;
}

}  // namespace tridex::app
