// renderer/image/image.hpp - 8-bit RGBA images on the CPU, PNG files, side-by-side stereo composition.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tridex::renderer {

/// An RGBA image, 8 bits per channel, rows top to bottom, no padding: rgba.size() == width * height * 4.
struct Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba;

    /// A width x height image filled with one colour. Throws tridex::Error on a negative size.
    static Image filled(int width, int height, std::uint8_t r, std::uint8_t g, std::uint8_t b, std::uint8_t a = 255);
    /// Pointer to the 4 bytes of pixel (x, y); no bounds check.
    std::uint8_t* at(int x, int y) { return rgba.data() + (static_cast<std::size_t>(y) * width + x) * 4; }
    const std::uint8_t* at(int x, int y) const { return rgba.data() + (static_cast<std::size_t>(y) * width + x) * 4; }
};

/// Writes `image` as an RGBA PNG (stb_image_write). Throws tridex::Error naming `path` when the image
/// is empty or inconsistent (rgba.size() != width * height * 4) or the file cannot be written.
void write_png(const std::string& path, const Image& image);

/// Reads a PNG (any channel count, converted to RGBA 8 bit; stb_image). Throws tridex::Error naming
/// `path` when the file is missing or not a decodable image.
Image read_png(const std::string& path);

/// Swaps the first and third byte of every 4-byte pixel of `pixels` in place: BGRA memory order (a B8G8R8A8 image
/// read back from the GPU) to RGBA, or back. A trailing partial pixel (size not a multiple of 4) is left alone.
void swap_red_blue(std::vector<std::uint8_t>& pixels);

/// Left and right placed next to each other (left at x = 0), width = left.width + right.width.
/// Throws tridex::Error when the heights differ or an image is inconsistent.
Image side_by_side(const Image& left, const Image& right);

}  // namespace tridex::renderer
