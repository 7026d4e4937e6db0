// Tests of renderer/image/image and image_compare: PNG round trip, side-by-side, tolerant comparison.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/error.hpp"
#include "renderer/image/image.hpp"
#include "renderer/image/image_compare.hpp"

namespace tridex::renderer {
namespace {

Image gradient(int w, int h) {
    Image img = Image::filled(w, h, 0, 0, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::uint8_t* p = img.at(x, y);
            p[0] = static_cast<std::uint8_t>(x * 17);
            p[1] = static_cast<std::uint8_t>(y * 29);
            p[2] = static_cast<std::uint8_t>(x * y);
            p[3] = static_cast<std::uint8_t>(200 + x);
        }
    return img;
}

TEST(Image, PngRoundTripIsLossless) {
    const Image a = gradient(13, 7);
    const std::string path = (std::filesystem::temp_directory_path() / "tridex_test_image.png").string();
    write_png(path, a);
    const Image b = read_png(path);
    EXPECT_EQ(b.width, 13);
    EXPECT_EQ(b.height, 7);
    EXPECT_EQ(a.rgba, b.rgba);
    std::filesystem::remove(path);
}

TEST(Image, PngErrorsNameThePath) {
    try {
        write_png("/nonexistent-dir/x.png", gradient(2, 2));
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.png"), std::string::npos);
    }
    EXPECT_THROW(write_png("/tmp/empty.png", Image{}), Error);
    Image bad = gradient(2, 2);
    bad.rgba.pop_back();
    EXPECT_THROW(write_png("/tmp/bad.png", bad), Error);
    EXPECT_THROW(read_png("/nonexistent-dir/x.png"), Error);
}

TEST(Image, SideBySidePlacesLeftThenRight) {
    const Image l = Image::filled(3, 2, 10, 20, 30);
    const Image r = gradient(4, 2);
    const Image s = side_by_side(l, r);
    ASSERT_EQ(s.width, 7);
    ASSERT_EQ(s.height, 2);
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 3; ++x) EXPECT_EQ(std::vector<std::uint8_t>(s.at(x, y), s.at(x, y) + 4),
                                              std::vector<std::uint8_t>(l.at(x, y), l.at(x, y) + 4));
        for (int x = 0; x < 4; ++x) EXPECT_EQ(std::vector<std::uint8_t>(s.at(3 + x, y), s.at(3 + x, y) + 4),
                                              std::vector<std::uint8_t>(r.at(x, y), r.at(x, y) + 4));
    }
    EXPECT_THROW(side_by_side(l, gradient(3, 3)), Error);
}

TEST(Image, SwapRedBlueTurnsBgraIntoRgbaAndBack) {
    std::vector<std::uint8_t> px = {1, 2, 3, 4, 10, 20, 30, 40, 7, 8};  // two pixels and a partial one
    swap_red_blue(px);
    EXPECT_EQ(px, (std::vector<std::uint8_t>{3, 2, 1, 4, 30, 20, 10, 40, 7, 8}));
    swap_red_blue(px);
    EXPECT_EQ(px, (std::vector<std::uint8_t>{1, 2, 3, 4, 10, 20, 30, 40, 7, 8}));
}

TEST(ImageCompare, CountsPixelsWithinTolerance) {
    Image a = gradient(10, 10);
    Image b = a;
    b.at(0, 0)[0] = static_cast<std::uint8_t>(b.at(0, 0)[0] + 3);  // within 3
    b.at(5, 5)[2] = static_cast<std::uint8_t>(b.at(5, 5)[2] + 4);  // outside 3
    b.at(9, 9)[3] = static_cast<std::uint8_t>(b.at(9, 9)[3] - 50);
    const ImageComparison c = compare_images(a, b, 3);
    EXPECT_EQ(c.pixels, 100u);
    EXPECT_EQ(c.within, 98u);
    EXPECT_EQ(c.max_channel_diff, 50);
    EXPECT_DOUBLE_EQ(c.fraction_within(), 0.98);
    const Image d = difference_image(a, b, 3);
    EXPECT_EQ(d.at(0, 0)[0], 12);   // grey 3 * 4
    EXPECT_EQ(d.at(5, 5)[0], 255);  // red: over tolerance
    EXPECT_EQ(d.at(5, 5)[1], 0);
    EXPECT_EQ(d.at(1, 1)[0], 0);
    EXPECT_THROW(compare_images(a, gradient(10, 9), 3), Error);
}

}  // namespace
}  // namespace tridex::renderer
