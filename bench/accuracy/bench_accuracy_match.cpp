// bench/accuracy/bench_accuracy_match.cpp - tridex against OpenVDB at matched error (see the header).
#include "bench/accuracy/bench_accuracy_match.hpp"

#include <algorithm>
#include <cstdio>

namespace tridex::bench::accuracy {

std::vector<MatchedRun> match_openvdb(const std::vector<AccuracyRow>& rows) {
    std::vector<MatchedRun> out;
    for (const AccuracyRow& o : rows) {
        if (o.method != "openvdb" || !(o.time_per_segment_s > 0.0)) continue;
        std::vector<std::string> paths;
        for (const AccuracyRow& t : rows)
            if (t.method == "tridex" && t.program == o.program && std::find(paths.begin(), paths.end(), t.path) == paths.end())
                paths.push_back(t.path);
        for (const std::string& path : paths) {
            const AccuracyRow* best = nullptr;
            for (const AccuracyRow& t : rows) {
                if (t.method != "tridex" || t.program != o.program || t.path != path || !(t.time_per_segment_s > 0.0)) continue;
                if (!(t.max_error_m <= o.max_error_m)) continue;
                if (!best || t.time_per_segment_s < best->time_per_segment_s ||
                    (t.time_per_segment_s == best->time_per_segment_s && t.n < best->n))
                    best = &t;
            }
            MatchedRun m{o.program, path, o.n, o.max_error_m, o.time_per_segment_s};
            if (best) {
                m.tridex_n = best->n;
                m.tridex_max_error_m = best->max_error_m;
                m.tridex_time_s = best->time_per_segment_s;
                m.ratio = o.time_per_segment_s / best->time_per_segment_s;
            }
            out.push_back(m);
        }
    }
    return out;
}

double worst_ratio(const std::vector<MatchedRun>& matched, const std::string& program, const std::string& path) {
    double worst = -1.0;
    for (const MatchedRun& m : matched) {
        if (m.program != program || m.path != path) continue;
        if (worst < 0.0 || m.ratio < worst) worst = m.ratio;
    }
    return worst;
}

void print_matched(const std::vector<MatchedRun>& matched) {
    if (matched.empty()) return;
    std::printf("matched error: per openvdb run, the fastest tridex run (per path, any N) with max error <= openvdb's; "
                "ratio = openvdb / tridex time per segment\n");
    std::printf("  %-11s %-6s %4s %8s %9s   %4s %8s %9s %8s\n", "program", "path", "vdbN", "vdb_mm", "vdb_us", "N", "max_mm",
                "t/seg_us", "ratio");
    for (const MatchedRun& m : matched) {
        std::printf("  %-11s %-6s %4d %8.4f %9.2f   ", m.program.c_str(), m.path.c_str(), m.openvdb_n, 1e3 * m.openvdb_max_error_m,
                    1e6 * m.openvdb_time_s);
        if (m.tridex_n == 0) std::printf("   - (no tridex run as accurate)\n");
        else std::printf("%4d %8.4f %9.2f %8.1f\n", m.tridex_n, 1e3 * m.tridex_max_error_m, 1e6 * m.tridex_time_s, m.ratio);
    }
    std::printf("worst matched ratio per program (0: an openvdb run no tridex run matches):\n");
    std::vector<std::pair<std::string, std::string>> seen;
    for (const MatchedRun& m : matched) {
        const std::pair<std::string, std::string> key{m.program, m.path};
        if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
        seen.push_back(key);
        std::printf("  %-11s %-6s %8.1f\n", m.program.c_str(), m.path.c_str(), worst_ratio(matched, m.program, m.path));
    }
}

}  // namespace tridex::bench::accuracy
