// renderer/image/image.cpp - PNG input/output through stb (static implementation, private to this file).
#include "renderer/image/image.hpp"

#include <algorithm>
#include <cstring>
#include <utility>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>

namespace tridex::renderer {
namespace {

bool consistent(const Image& image) {
    return image.width > 0 && image.height > 0 &&
           image.rgba.size() == static_cast<std::size_t>(image.width) * image.height * 4;
}

}  // namespace

Image Image::filled(int width, int height, std::uint8_t r, std::uint8_t g, std::uint8_t b, std::uint8_t a) {
    if (width < 0 || height < 0) throw Error("Image::filled: negative size");
    Image img{width, height, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height * 4)};
    for (std::size_t i = 0; i < img.rgba.size(); i += 4) {
        img.rgba[i] = r;
        img.rgba[i + 1] = g;
        img.rgba[i + 2] = b;
        img.rgba[i + 3] = a;
    }
    return img;
}

void write_png(const std::string& path, const Image& image) {
    if (!consistent(image))
        throw Error(path + ": cannot write an empty or inconsistent image (" + std::to_string(image.width) + "x" +
                    std::to_string(image.height) + ", " + std::to_string(image.rgba.size()) + " bytes)");
    // Encode in memory, then write the file whole (a full disk leaves no cut PNG behind and names this file).
    std::string bytes;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
    };
    if (stbi_write_png_to_func(append, &bytes, image.width, image.height, 4, image.rgba.data(), image.width * 4) == 0)
        throw Error(path + ": could not encode the PNG image");
    write_file_atomically(path, bytes);
}

Image read_png(const std::string& path) {
    int w = 0, h = 0, channels = 0;
    stbi_uc* data = stbi_load(path.c_str(), &w, &h, &channels, 4);
    if (!data) throw Error(path + ": could not read the PNG file (" + stbi_failure_reason() + ")");
    Image img{w, h, std::vector<std::uint8_t>(data, data + static_cast<std::size_t>(w) * h * 4)};
    stbi_image_free(data);
    return img;
}

void swap_red_blue(std::vector<std::uint8_t>& pixels) {
    for (std::size_t i = 0; i + 3 < pixels.size(); i += 4) std::swap(pixels[i], pixels[i + 2]);
}

Image side_by_side(const Image& left, const Image& right) {
    if (!consistent(left) || !consistent(right))
        throw Error("side_by_side: an input image is empty or inconsistent");
    if (left.height != right.height)
        throw Error("side_by_side: heights differ (" + std::to_string(left.height) + " vs " +
                    std::to_string(right.height) + ")");
    Image out{left.width + right.width, left.height,
              std::vector<std::uint8_t>(static_cast<std::size_t>(left.width + right.width) * left.height * 4)};
    for (int y = 0; y < out.height; ++y) {
        std::memcpy(out.at(0, y), left.at(0, y), static_cast<std::size_t>(left.width) * 4);
        std::memcpy(out.at(left.width, y), right.at(0, y), static_cast<std::size_t>(right.width) * 4);
    }
    return out;
}

}  // namespace tridex::renderer
