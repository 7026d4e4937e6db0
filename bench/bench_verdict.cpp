// bench/bench_verdict.cpp - a row's verdict against its target, and its words.
#include "bench/bench_verdict.hpp"

namespace tridex::bench {

Verdict verdict_of(std::size_t timed, bool within) {
    if (timed == 0) return Verdict::kNotMeasured;
    return within ? Verdict::kMet : Verdict::kOver;
}

const char* verdict_text(Verdict v) {
    switch (v) {
        case Verdict::kMet: return "target met";
        case Verdict::kOver: return "over target";
        case Verdict::kNotMeasured: return "not measured";
    }
    return "not measured";
}

}  // namespace tridex::bench
