// renderer/image/image_compare.cpp - per-channel image differences.
#include "renderer/image/image_compare.hpp"

#include <algorithm>
#include <cstdlib>
#include <string>

#include "core/error.hpp"

namespace tridex::renderer {
namespace {

void check_pair(const Image& a, const Image& b) {
    const auto ok = [](const Image& i) {
        return i.width >= 0 && i.height >= 0 && i.rgba.size() == static_cast<std::size_t>(i.width) * i.height * 4;
    };
    if (!ok(a) || !ok(b)) throw Error("compare_images: an image is inconsistent (size vs pixel bytes)");
    if (a.width != b.width || a.height != b.height)
        throw Error("compare_images: sizes differ (" + std::to_string(a.width) + "x" + std::to_string(a.height) +
                    " vs " + std::to_string(b.width) + "x" + std::to_string(b.height) + ")");
}

int pixel_diff(const std::uint8_t* p, const std::uint8_t* q) {
    int m = 0;
    for (int c = 0; c < 4; ++c) m = std::max(m, std::abs(int(p[c]) - int(q[c])));
    return m;
}

}  // namespace

ImageComparison compare_images(const Image& a, const Image& b, int tolerance) {
    check_pair(a, b);
    ImageComparison out;
    out.pixels = static_cast<std::size_t>(a.width) * a.height;
    for (std::size_t i = 0; i < out.pixels; ++i) {
        const int d = pixel_diff(&a.rgba[i * 4], &b.rgba[i * 4]);
        out.max_channel_diff = std::max(out.max_channel_diff, d);
        if (d <= tolerance) ++out.within;
    }
    return out;
}

Image difference_image(const Image& a, const Image& b, int tolerance) {
    check_pair(a, b);
    Image out = Image::filled(a.width, a.height, 0, 0, 0);
    for (std::size_t i = 0; i < static_cast<std::size_t>(a.width) * a.height; ++i) {
        const int d = pixel_diff(&a.rgba[i * 4], &b.rgba[i * 4]);
        std::uint8_t* o = &out.rgba[i * 4];
        if (d > tolerance) {
            o[0] = 255;
        } else {
            const auto g = static_cast<std::uint8_t>(std::min(255, d * 4));
            o[0] = o[1] = o[2] = g;
        }
    }
    return out;
}

}  // namespace tridex::renderer
