// app/study/study_plot.cpp - a small line plot rasterised into an RGBA image.
#include "app/study/study_plot.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "app/study/study_analyze.hpp"
#include "renderer/image/image.hpp"

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

// 3 x 5 pixel glyphs for digits and '.', one row per entry, bit 2 = left column.
const std::array<std::array<std::uint8_t, 5>, 11> kGlyphs{{{7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7},
                                                           {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1}, {7, 4, 7, 1, 7},
                                                           {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1}, {7, 5, 7, 5, 7},
                                                           {7, 5, 7, 1, 7}, {0, 0, 0, 0, 2}}};

// Draws `text` (digits and '.') with its top-right corner at (x, y), pixels scaled by 2.
void text_right(Image& im, const std::string& text, int x, int y, Rgb c) {
    int cx = x - static_cast<int>(text.size()) * 8;
    for (char ch : text) {
        const int g = ch == '.' ? 10 : (ch >= '0' && ch <= '9' ? ch - '0' : -1);
        if (g >= 0)
            for (int row = 0; row < 5; ++row)
                for (int col = 0; col < 3; ++col)
                    if (kGlyphs[static_cast<std::size_t>(g)][static_cast<std::size_t>(row)] & (4 >> col))
                        for (int k = 0; k < 4; ++k) put(im, cx + col * 2 + k % 2, y + row * 2 + k / 2, c);
        cx += 8;
    }
}

double nice_ceiling(double v) {
    if (!(v > 0.0)) return 1.0;
    const double p = std::pow(10.0, std::floor(std::log10(v)));
    for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
        if (m * p >= v) return m * p;
    return 10.0 * p;
}

}  // namespace

void plot_group_deviation(const std::string& path, const std::vector<const TrialAnalysis*>& trials) {
    const int w = 800, h = 500, left = 70, right = 20, top = 20, bottom = 40;
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
    static const Rgb colours[] = {{31, 119, 180}, {255, 127, 14}, {44, 160, 44},  {214, 39, 40},  {148, 103, 189},
                                  {140, 86, 75},  {227, 119, 194}, {127, 127, 127}, {188, 189, 34}, {23, 190, 207}};
    for (std::size_t k = 0; k < trials.size(); ++k) {
        const TrialAnalysis& t = *trials[k];
        const Rgb c = colours[k % std::size(colours)];
        for (std::size_t i = 1; i < t.progress.size(); ++i)
            line(im, px(t.progress[i - 1]), py(t.deviation_m[i - 1] * 1e3), px(t.progress[i]), py(t.deviation_m[i] * 1e3), c, 2);
    }
    renderer::write_png(path, im);
}

}  // namespace tridex::app::study
