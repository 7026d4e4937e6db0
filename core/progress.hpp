// core/progress.hpp - how long work tells how far it got, without knowing who listens (a terminal, a log, a test).
#pragma once

#include <algorithm>
#include <functional>

namespace tridex {

/// Receives the fraction of one long piece of work done so far, 0..1 (non-decreasing), called from the thread that
/// runs the work (never from two threads at once). The work may call it often (once per slice of tiles, rays or
/// records): the receiver decides what to show and how often (app/support/progress.hpp draws a bar on a terminal).
/// An empty ProgressFn means nobody listens; the work then costs nothing extra. The receiver must not throw.
using ProgressFn = std::function<void(double fraction)>;

/// Calls `fn` with done / total, clamped to 0..1, when fn is set and total > 0; does nothing otherwise.
inline void report_progress(const ProgressFn& fn, double done, double total) {
    if (fn && total > 0.0) fn(std::clamp(done / total, 0.0, 1.0));
}

/// The part [from, to] (fractions, 0 <= from <= to <= 1) of `fn`'s range, as a ProgressFn of its own: a phase of
/// a longer piece of work reports 0..1 and `fn` sees from..to. Empty when fn is empty.
inline ProgressFn progress_part(const ProgressFn& fn, double from, double to) {
    if (!fn) return {};
    return [fn, from, to](double f) { fn(from + (to - from) * std::clamp(f, 0.0, 1.0)); };
}

}  // namespace tridex
