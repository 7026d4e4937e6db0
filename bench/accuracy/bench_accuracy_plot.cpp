// bench/accuracy/bench_accuracy_plot.cpp - gnuplot scripts and PNGs for bench --accuracy.
#include "bench/accuracy/bench_accuracy_plot.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"

namespace tridex::bench::accuracy {

std::vector<std::string> write_accuracy_plots(const std::vector<AccuracyRow>& rows, const std::string& out) {
    std::vector<std::string> pngs;
    if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
        std::printf("plots skipped: gnuplot not found (Debian gnuplot-nox)\n");
        return pngs;
    }
    std::vector<std::string> programs, series;
    for (const AccuracyRow& r : rows) {
        if (r.program == "paint") continue;
        if (std::find(programs.begin(), programs.end(), r.program) == programs.end()) programs.push_back(r.program);
        const std::string s = r.method + " " + r.path;
        if (std::find(series.begin(), series.end(), s) == series.end()) series.push_back(s);
    }
    for (const std::string& prog : programs) {
        const std::filesystem::path dir(out);
        const std::string dat = (dir / ("accuracy_" + prog + ".dat")).string();
        const std::string gp = (dir / ("accuracy_" + prog + ".gp")).string();
        const std::string png = (dir / ("accuracy_" + prog + ".png")).string();
        std::ofstream d(dat);
        std::ofstream g(gp);
        if (!d || !g) throw Error(dat + ": cannot open for writing");
        std::vector<std::string> used;
        for (const std::string& s : series) {
            bool any = false;
            for (const AccuracyRow& r : rows)
                if (r.program == prog && r.method + " " + r.path == s && r.time_per_segment_s > 0.0) {
                    if (!any) d << "# " << s << "\n";
                    any = true;
                    d << r.max_error_m << " " << r.time_per_segment_s << " " << r.n << "\n";
                }
            if (any) {
                d << "\n\n";
                used.push_back(s);
            }
        }
        g << "set terminal pngcairo size 800,560\nset output '" << png << "'\n"
          << "set title 'bench --accuracy: " << prog << " (labels: N)' noenhanced\nset logscale xy\n"
          << "set xlabel 'max vertex error, m'\nset ylabel 'time per segment, s'\nset key outside bottom center horizontal\n"
          << "set grid\nplot ";
        for (std::size_t i = 0; i < used.size(); ++i)
            g << (i ? ", " : "") << "'" << dat << "' index " << i << " using 1:2 with linespoints title '" << used[i]
              << "', '' index " << i << " using 1:2:3 with labels offset 1,0.7 notitle";
        g << "\n";
        g.close();
        d.close();
        if (used.empty()) continue;
        const std::string cmd = "gnuplot '" + gp + "' > /dev/null 2>&1";
        if (std::system(cmd.c_str()) == 0) pngs.push_back(png);
        else std::printf("plot %s: gnuplot failed (%s)\n", prog.c_str(), gp.c_str());
    }
    return pngs;
}

}  // namespace tridex::bench::accuracy
