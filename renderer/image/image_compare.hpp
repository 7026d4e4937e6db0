// renderer/image/image_compare.hpp - tolerant comparison of two images (golden-image tests).
#pragma once

#include <cstddef>

#include "renderer/image/image.hpp"

namespace tridex::renderer {

/// Outcome of compare_images().
struct ImageComparison {
    std::size_t pixels = 0;         ///< pixels compared (width * height)
    std::size_t within = 0;         ///< pixels whose every channel differs by <= the tolerance
    int max_channel_diff = 0;       ///< largest |a - b| over all channels and pixels, 0..255
    /// Fraction of pixels within the tolerance, 0..1 (1 for an empty image).
    double fraction_within() const { return pixels ? static_cast<double>(within) / pixels : 1.0; }
};

/// Compares a and b channel by channel (RGBA): a pixel is "within" when all four |a - b| <= tolerance.
/// Throws tridex::Error when sizes differ or an image is inconsistent.
ImageComparison compare_images(const Image& a, const Image& b, int tolerance);

/// A visual difference image: black where the pixels are equal, grey levels proportional to the largest
/// channel difference (x4, clamped) and pure red where it exceeds `tolerance`. Same errors as compare_images.
Image difference_image(const Image& a, const Image& b, int tolerance);

}  // namespace tridex::renderer
