// app/commands/study/study_plot.cpp - a small line plot rasterised into an RGBA image.
#include "app/commands/study/study_plot.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "app/commands/study/study_analyze.hpp"
#include "renderer/image/image.hpp"
#include "renderer/scene/overlay_text.hpp"

namespace tridex::app::study {

namespace {

using renderer::Image;

struct Rgb {
    std::uint8_t r, g, b;
};

void put(Image& im, int x, int y, Rgb c) {
    if (x < 0 || y < 0 || x >= im.width || y >= im.height) return;
    std::uint8_t* p = im.at(x, y);
    p[0] = c.r, p[1] = c.g, p[2] = c.b, p[3] = 255;
}

void line(Image& im, double x0, double y0, double x1, double y1, Rgb c, int thick = 1) {
    const int steps = static_cast<int>(std::max(std::fabs(x1 - x0), std::fabs(y1 - y0))) + 1;
    for (int i = 0; i <= steps; ++i) {
        const double t = static_cast<double>(i) / steps;
        const int x = static_cast<int>(std::lround(x0 + t * (x1 - x0))), y = static_cast<int>(std::lround(y0 + t * (y1 - y0)));
        for (int dy = 0; dy < thick; ++dy)
            for (int dx = 0; dx < thick; ++dx) put(im, x + dx, y + dy, c);
    }
}

// Draws `text` with its top-left corner at (x, y), `scale` pixels per font unit (stb_easy_font's glyphs through the
// overlay's text mesh: axis-aligned quads, each two triangles, filled as their bounding boxes).
void text_at(Image& im, const std::string& text, double x, double y, double scale, Rgb c) {
    const TriMesh m = renderer::overlay_text_mesh(text, x, y, scale);
    for (const auto& t : m.triangles) {
        double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
        for (int k = 0; k < 3; ++k) {
            const Vec3& p = m.positions[static_cast<std::size_t>(t[k])];
            x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
        }
        for (int py = static_cast<int>(std::lround(y0)); py < static_cast<int>(std::lround(y1)); ++py)
            for (int px = static_cast<int>(std::lround(x0)); px < static_cast<int>(std::lround(x1)); ++px) put(im, px, py, c);
    }
}

// Draws `text` with its top-right corner at (x, y).
void text_right(Image& im, const std::string& text, int x, int y, Rgb c) {
    const double scale = 2.0;
    text_at(im, text, x - renderer::overlay_text_extent(text, scale).width_px, y, scale, c);
}

// A trial's label in the legend.
std::string legend_label(const TrialAnalysis& t) { return t.row.participant + " trial " + std::to_string(t.row.trial); }

double nice_ceiling(double v) {
    if (!(v > 0.0)) return 1.0;
    const double p = std::pow(10.0, std::floor(std::log10(v)));
    for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
        if (m * p >= v) return m * p;
    return 10.0 * p;
}

}  // namespace

void plot_group_deviation(const std::string& path, const std::vector<const TrialAnalysis*>& trials) {
    // The legend's room right of the plot: its longest label, the line sample before it and a margin; the plot keeps
    // its 780 px whatever the participants' IDs.
    constexpr double kLegendScale = 1.5;
    int legend_px = 0;
    for (const TrialAnalysis* t : trials)
        legend_px = std::max(
            legend_px,
            static_cast<int>(std::ceil(renderer::overlay_text_extent(legend_label(*t), kLegendScale).width_px)));
    const int left = 70, right = std::max(150, 36 + legend_px + 12), top = 60, bottom = 60, w = 780 + left + right,
              h = 560;
    Image im = Image::filled(w, h, 255, 255, 255);
    double ymax = 0.0;
    for (const TrialAnalysis* t : trials)
        for (double d : t->deviation_m) ymax = std::max(ymax, d * 1e3);
    ymax = nice_ceiling(ymax);
    const double x_lo = -0.2, x_hi = 1.2;
    auto px = [&](double x) { return left + (std::clamp(x, x_lo, x_hi) - x_lo) / (x_hi - x_lo) * (w - left - right); };
    auto py = [&](double y) { return (h - bottom) - std::clamp(y, 0.0, ymax) / ymax * (h - top - bottom); };
    const Rgb grid{220, 220, 220}, axis{0, 0, 0}, tube_band{235, 245, 235};
    for (int y = top; y < h - bottom; ++y)  // the tube proper, shaded
        line(im, px(0.0), y, px(1.0), y, tube_band);
    for (int i = 0; i <= 7; ++i) line(im, px(x_lo + 0.2 * i), top, px(x_lo + 0.2 * i), h - bottom, grid);
    for (int i = 0; i <= 5; ++i) {
        const double v = ymax * i / 5.0;
        line(im, left, py(v), w - right, py(v), grid);
        char buf[32];
        std::snprintf(buf, sizeof buf, ymax < 5 ? "%.2f" : "%.1f", v);
        text_right(im, buf, left - 6, static_cast<int>(py(v)) - 5, axis);
    }
    for (int i = 0; i <= 7; ++i) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.1f", std::fabs(x_lo + 0.2 * i) < 1e-9 ? 0.0 : x_lo + 0.2 * i);
        if (x_lo + 0.2 * i >= -1e-9) text_right(im, buf, static_cast<int>(px(x_lo + 0.2 * i)) + 12, h - bottom + 8, axis);
    }
    line(im, left, h - bottom, w - right, h - bottom, axis, 2);
    line(im, left, top, left, h - bottom, axis, 2);
    const std::string group = trials.empty() ? std::string() : trials.front()->row.group;
    text_at(im, group + " group: deviation of the wand from the tube wall, one line per test trial", left, 10, 2.0, axis);
    text_at(im, "position along the tube (0 entry, 1 exit; shaded: the tube, outside: the funnels)", left, h - bottom + 30,
            1.5, axis);
    text_at(im, "deviation (mm): per tick, the mean of the wand's two points (analyze's max: the worse point alone)",
            10, top - 24, 1.5, axis);
    static const Rgb colours[] = {{31, 119, 180}, {255, 127, 14}, {44, 160, 44},  {214, 39, 40},  {148, 103, 189},
                                  {140, 86, 75},  {227, 119, 194}, {127, 127, 127}, {188, 189, 34}, {23, 190, 207}};
    for (std::size_t k = 0; k < trials.size(); ++k) {
        const TrialAnalysis& t = *trials[k];
        const Rgb c = colours[k % std::size(colours)];
        for (std::size_t i = 1; i < t.progress.size(); ++i)
            line(im, px(t.progress[i - 1]), py(t.deviation_m[i - 1] * 1e3), px(t.progress[i]), py(t.deviation_m[i] * 1e3), c, 2);
        // Legend: participant and trial in the line's colour, right of the plot.
        if (k < 30) {
            const int ly = top + 14 * static_cast<int>(k);
            line(im, w - right + 10, ly + 5, w - right + 30, ly + 5, c, 2);
            text_at(im, legend_label(t), w - right + 36, ly, kLegendScale, axis);
        }
    }
    renderer::write_png(path, im);
}

}  // namespace tridex::app::study
