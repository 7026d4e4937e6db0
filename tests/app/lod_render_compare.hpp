// tests/app/lod_render_compare.hpp - a stereo frame drawn with levels of detail against its full-resolution frame:
// silhouette mismatch, colour difference and holes (cracks that show the background through the surface).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

struct LodImageDiff {
    std::size_t pixels = 0, mismatched = 0, holes = 0;
    double abs_sum = 0.0;     // |difference| summed over the RGB channels of every pixel, 0..255 each
    std::size_t far_off = 0;  // pixels with a channel more than 48 codes off (a visibly different pixel)
    double mean_abs() const { return pixels > 0 ? abs_sum / (3.0 * static_cast<double>(pixels)) : 0.0; }
};

// Object/background class per pixel of both eyes; `holes`: background pixels of `lod` whose four neighbours are
// all object in both renders (a crack would show the background through the surface).
inline LodImageDiff compare_lod_images(const renderer::StereoImages& lod, const renderer::StereoImages& full,
                                       const std::uint8_t* bg) {
    LodImageDiff d;
    const auto one = [&](const renderer::Image& a, const renderer::Image& b) {
        const auto is_bg = [&](const renderer::Image& im, int x, int y) {
            return std::equal(bg, bg + 3, im.rgba.data() + 4 * (static_cast<std::size_t>(y) * im.width + x));
        };
        for (int y = 0; y < a.height; ++y)
            for (int x = 0; x < a.width; ++x) {
                ++d.pixels;
                const std::size_t at = 4 * (static_cast<std::size_t>(y) * a.width + x);
                int worst = 0;
                for (int c = 0; c < 3; ++c) {
                    const int diff = std::abs(int(a.rgba[at + c]) - int(b.rgba[at + c]));
                    d.abs_sum += diff;
                    worst = std::max(worst, diff);
                }
                d.far_off += worst > 48 ? 1 : 0;
                const bool ba = is_bg(a, x, y), bb = is_bg(b, x, y);
                if (ba != bb) ++d.mismatched;
                if (ba && !bb && x > 0 && y > 0 && x + 1 < a.width && y + 1 < a.height && !is_bg(a, x - 1, y) &&
                    !is_bg(a, x + 1, y) && !is_bg(a, x, y - 1) && !is_bg(a, x, y + 1))
                    ++d.holes;
            }
    };
    one(lod.left, full.left);
    one(lod.right, full.right);
    return d;
}

// The desk's tolerance for a frame with levels against its full-resolution frame: prints one line starting with
// `what`, and expects the silhouette within half a percent of the pixels, a mean difference of at most 1.5 codes per
// channel, at most 1 % of the pixels visibly different (a channel more than 48 codes off) and no hole.
inline void expect_desk_match(const renderer::StereoImages& lod, const renderer::StereoImages& full,
                              const std::uint8_t* bg, const std::string& what) {
    const LodImageDiff d = compare_lod_images(lod, full, bg);
    const double mismatch = static_cast<double>(d.mismatched) / static_cast<double>(d.pixels);
    const double far_off = static_cast<double>(d.far_off) / static_cast<double>(d.pixels);
    std::printf("%s: triangles L %zu of %zu, groups L %zu, silhouette mismatch %.4f%%, mean |diff| %.3f, visibly "
                "different %.4f%%, holes %zu\n",
                what.c_str(), lod.stats.tile_triangles[0], full.stats.tile_triangles[0], lod.stats.groups_drawn[0],
                100.0 * mismatch, d.mean_abs(), 100.0 * far_off, d.holes);
    EXPECT_LE(mismatch, 0.005) << what;
    EXPECT_LE(d.mean_abs(), 1.5) << what;
    EXPECT_LE(far_off, 0.01) << what;
    EXPECT_EQ(d.holes, 0u) << what;
}

}  // namespace tridex::app
