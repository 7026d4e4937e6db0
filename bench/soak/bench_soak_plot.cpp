// bench/soak/bench_soak_plot.cpp - the soak's plot: memory and frame time per minute, as an SVG of two panels.
#include "bench/soak/bench_soak.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace tridex::bench {

namespace {

constexpr double kWidth = 760.0, kPanelH = 240.0, kLeft = 70.0, kRight = 20.0, kTop = 34.0, kGap = 60.0;

struct Series {
    std::vector<double> y;
    std::string colour, label;
};

std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", v);
    return b;
}

// A "nice" upper end for an axis from 0 holding `v`.
double nice_top(double v) {
    if (!(v > 0.0)) return 1.0;
    const double e = std::pow(10.0, std::floor(std::log10(v)));
    for (const double m : {1.0, 2.0, 2.5, 5.0, 10.0})
        if (m * e >= v * 1.05) return m * e;
    return 10.0 * e;
}

// One panel: axes from 0 with four grid lines, the series as polylines with points, against minutes 1..n.
void panel(std::ostringstream& s, double top_px, const std::string& title, const std::string& unit,
           const std::vector<int>& minutes, const std::vector<Series>& series) {
    const double w = kWidth - kLeft - kRight;
    double ymax = 0.0;
    for (const Series& se : series)
        for (const double v : se.y) ymax = std::max(ymax, v);
    ymax = nice_top(ymax);
    const int last = minutes.empty() ? 1 : std::max(1, minutes.back());
    const auto px = [&](int m) { return kLeft + w * (last > 1 ? (m - 1.0) / (last - 1.0) : 0.5); };
    const auto py = [&](double v) { return top_px + kPanelH * (1.0 - v / ymax); };
    s << "<text x='" << kLeft << "' y='" << top_px - 10 << "' font-size='14'>" << title << "</text>\n";
    for (int k = 0; k <= 4; ++k) {
        const double v = ymax * k / 4.0;
        s << "<line x1='" << kLeft << "' x2='" << kLeft + w << "' y1='" << py(v) << "' y2='" << py(v)
          << "' stroke='#ddd'/>\n<text x='" << kLeft - 6 << "' y='" << py(v) + 4
          << "' font-size='11' text-anchor='end'>" << num(v) << "</text>\n";
    }
    s << "<text x='14' y='" << top_px + kPanelH / 2 << "' font-size='11' transform='rotate(-90 14 "
      << top_px + kPanelH / 2 << ")' text-anchor='middle'>" << unit << "</text>\n";
    const int step = std::max(1, last / 10);
    for (int m = 1; m <= last; m += step)
        s << "<text x='" << px(m) << "' y='" << top_px + kPanelH + 15 << "' font-size='11' text-anchor='middle'>" << m
          << "</text>\n";
    s << "<text x='" << kLeft + w / 2 << "' y='" << top_px + kPanelH + 32
      << "' font-size='11' text-anchor='middle'>minute</text>\n";
    double legend_x = kLeft + w - 10;
    for (auto it = series.rbegin(); it != series.rend(); ++it) {
        s << "<text x='" << legend_x << "' y='" << top_px - 10 << "' font-size='12' text-anchor='end'>" << it->label
          << "</text>\n";
        legend_x -= 7.0 * static_cast<double>(it->label.size()) + 8.0;
        s << "<rect x='" << legend_x - 14 << "' y='" << top_px - 19 << "' width='14' height='10' fill='" << it->colour
          << "'/>\n";
        legend_x -= 30.0;
    }
    for (const Series& se : series) {
        s << "<polyline fill='none' stroke='" << se.colour << "' stroke-width='2' points='";
        for (std::size_t i = 0; i < se.y.size(); ++i) s << px(minutes[i]) << "," << py(se.y[i]) << " ";
        s << "'/>\n";
        for (std::size_t i = 0; i < se.y.size(); ++i)
            s << "<circle cx='" << px(minutes[i]) << "' cy='" << py(se.y[i]) << "' r='2.5' fill='" << se.colour
              << "'/>\n";
    }
}

}  // namespace

void write_soak_plot(const std::vector<SoakMinute>& rows, const std::string& path) {
    std::vector<int> minutes;
    Series rss{{}, "#1f77b4", "resident memory"}, p50{{}, "#2ca02c", "frame median"}, p99{{}, "#d62728", "frame p99"};
    for (const SoakMinute& m : rows) {
        minutes.push_back(m.minute);
        rss.y.push_back(m.rss_mb);
        p50.y.push_back(m.frame_p50_ms);
        p99.y.push_back(m.frame_p99_ms);
    }
    std::ostringstream s;
    const double height = kTop + 2.0 * kPanelH + kGap + 50.0;
    s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << kWidth << "' height='" << height
      << "' font-family='sans-serif'>\n<rect width='100%' height='100%' fill='white'/>\n";
    panel(s, kTop, "bench --soak: resident memory per minute", "MB", minutes, {rss});
    panel(s, kTop + kPanelH + kGap, "frame time per minute (draw + readback)", "ms", minutes, {p50, p99});
    s << "</svg>\n";
    std::ofstream f(path);
    if (!f || !(f << s.str())) throw Error(path + ": cannot write the plot");
}

}  // namespace tridex::bench
