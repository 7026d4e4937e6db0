// Tests of the stereo outputs: names, quad support, exact compositions, box resampling, anaglyph matrices.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "renderer/image/image.hpp"
#include "renderer/output/stereo_output.hpp"

namespace tridex::renderer {
namespace {

/// A w x h image whose pixel (x, y) is (base + x, base + 2 y, tag, 255): every pixel says where it came from.
Image coded(int w, int h, std::uint8_t base, std::uint8_t tag) {
    Image img = Image::filled(w, h, 0, 0, 0, 255);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            img.at(x, y)[0] = static_cast<std::uint8_t>(base + x);
            img.at(x, y)[1] = static_cast<std::uint8_t>(base + 2 * y);
            img.at(x, y)[2] = tag;
        }
    return img;
}

bool same_pixel(const Image& a, int ax, int ay, const Image& b, int bx, int by) {
    for (int c = 0; c < 4; ++c)
        if (a.at(ax, ay)[c] != b.at(bx, by)[c]) return false;
    return true;
}

TEST(StereoOutput, NamesRoundTripAndUnknownNameListsTheValidOnes) {
    EXPECT_EQ(all_stereo_outputs().size(), 8u);
    for (StereoOutput o : all_stereo_outputs()) EXPECT_EQ(parse_stereo_output(std::string(to_string(o))), o);
    EXPECT_EQ(parse_stereo_output("side-by-side-half"), StereoOutput::kSideBySideHalf);
    try {
        parse_stereo_output("sbs");
        FAIL() << "no throw";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("'sbs'"), std::string::npos) << m;
        EXPECT_NE(m.find("quad, frame-sequential, side-by-side, side-by-side-half, top-bottom, top-bottom-half, "
                         "anaglyph, mono"),
                  std::string::npos)
            << m;
    }
    EXPECT_THROW(parse_stereo_output("Anaglyph"), Error);  // exact, lower case
    EXPECT_EQ(parse_anaglyph_method("gray"), AnaglyphMethod::kGray);
    EXPECT_THROW(parse_anaglyph_method("grey"), Error);
}

TEST(StereoOutput, OnlyMonoSkipsTheSecondEye) {
    for (StereoOutput o : all_stereo_outputs()) EXPECT_EQ(needs_both_eyes(o), o != StereoOutput::kMono) << to_string(o);
}

TEST(StereoOutput, OutputSizes) {
    EXPECT_EQ(output_size(StereoOutput::kSideBySide, 640, 480), std::make_pair(1280, 480));
    EXPECT_EQ(output_size(StereoOutput::kTopBottom, 640, 480), std::make_pair(640, 960));
    for (StereoOutput o : {StereoOutput::kSideBySideHalf, StereoOutput::kTopBottomHalf, StereoOutput::kAnaglyph,
                           StereoOutput::kMono, StereoOutput::kQuad, StereoOutput::kFrameSequential})
        EXPECT_EQ(output_size(o, 640, 480), std::make_pair(640, 480)) << to_string(o);
    EXPECT_THROW(output_size(StereoOutput::kMono, 0, 480), Error);
}

TEST(StereoOutput, EyeSizeForAnOutputInvertsOutputSize) {
    for (StereoOutput o : all_stereo_outputs()) {
        const auto [w, h] = output_size(o, 640, 480);
        EXPECT_EQ(eye_size_for_output(o, w, h), std::make_pair(640, 480)) << to_string(o);
    }
    EXPECT_EQ(eye_size_for_output(StereoOutput::kSideBySide, 1, 5), std::make_pair(1, 5));  // never below 1x1
    EXPECT_THROW(eye_size_for_output(StereoOutput::kMono, 0, 480), Error);
}

TEST(StereoOutput, QuadNeedsTwoLayersAndOtherwiseSaysWhatWorks) {
    const OutputSupport ok = check_output_support(StereoOutput::kQuad, 2);
    EXPECT_TRUE(ok.supported);
    EXPECT_TRUE(ok.message.empty());
    const OutputSupport no = check_output_support(StereoOutput::kQuad, 1);
    EXPECT_FALSE(no.supported);
    EXPECT_EQ(no.message,
              "stereo output 'quad' needs a swapchain with 2 image layers but the surface reports "
              "maxImageArrayLayers = 1; outputs that will work: frame-sequential, side-by-side, side-by-side-half, "
              "top-bottom, top-bottom-half, anaglyph, mono");
    for (StereoOutput o : all_stereo_outputs()) {
        if (o == StereoOutput::kQuad) continue;
        EXPECT_TRUE(check_output_support(o, 1).supported) << to_string(o);
    }
    EXPECT_EQ(supported_outputs(1).size(), 7u);
    EXPECT_EQ(supported_outputs(2).size(), 8u);
}

TEST(StereoOutput, SideBySideAndTopBottomFullResolutionCopyEveryPixel) {
    const Image l = coded(5, 3, 10, 1), r = coded(5, 3, 100, 2);
    const Image sbs = compose(StereoOutput::kSideBySide, l, r);
    ASSERT_EQ(sbs.width, 10);
    ASSERT_EQ(sbs.height, 3);
    const Image tb = compose(StereoOutput::kTopBottom, l, r);
    ASSERT_EQ(tb.width, 5);
    ASSERT_EQ(tb.height, 6);
    const Image sbs_swapped = compose(StereoOutput::kSideBySide, l, r, {.swap_eyes = true});
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x) {
            EXPECT_TRUE(same_pixel(sbs, x, y, l, x, y));
            EXPECT_TRUE(same_pixel(sbs, x + 5, y, r, x, y));
            EXPECT_TRUE(same_pixel(tb, x, y, l, x, y));
            EXPECT_TRUE(same_pixel(tb, x, y + 3, r, x, y));
            EXPECT_TRUE(same_pixel(sbs_swapped, x, y, r, x, y));
            EXPECT_TRUE(same_pixel(sbs_swapped, x + 5, y, l, x, y));
        }
}

TEST(StereoOutput, HalfResolutionAveragesPixelPairs) {
    // Left: columns alternate 10 and 21 -> pairs average (31 + 1) / 2 = 16; right: rows alternate 40 and 50 -> 45.
    Image l = Image::filled(4, 4, 0, 0, 0, 255), r = Image::filled(4, 4, 0, 0, 0, 255);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            l.at(x, y)[0] = (x % 2) ? 21 : 10;
            r.at(x, y)[1] = (y % 2) ? 50 : 40;
        }
    const Image sbs = compose(StereoOutput::kSideBySideHalf, l, r);
    ASSERT_EQ(sbs.width, 4);
    ASSERT_EQ(sbs.height, 4);
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 2; ++x) EXPECT_EQ(sbs.at(x, y)[0], 16) << x << "," << y;
        // The right eye squeezed horizontally keeps its rows.
        for (int x = 2; x < 4; ++x) EXPECT_EQ(sbs.at(x, y)[1], (y % 2) ? 50 : 40) << x << "," << y;
    }
    const Image tb = compose(StereoOutput::kTopBottomHalf, l, r);
    ASSERT_EQ(tb.width, 4);
    ASSERT_EQ(tb.height, 4);
    for (int x = 0; x < 4; ++x) {
        for (int y = 0; y < 2; ++y) EXPECT_EQ(tb.at(x, y)[0], (x % 2) ? 21 : 10);
        for (int y = 2; y < 4; ++y) EXPECT_EQ(tb.at(x, y)[1], 45);
        for (int y = 0; y < 4; ++y) EXPECT_EQ(tb.at(x, y)[3], 255);
    }
}

TEST(StereoOutput, BoxResampleWeighsFractionalCoverage) {
    // 5 -> 2 pixels: each output pixel covers 2.5 source pixels, weights 0.4, 0.4, 0.2 and 0.2, 0.4, 0.4.
    Image src = Image::filled(5, 1, 0, 0, 0, 255);
    for (int x = 0; x < 5; ++x) src.at(x, 0)[0] = static_cast<std::uint8_t>(10 * x);
    const Image out = resample_box(src, 2, 1);
    EXPECT_EQ(out.at(0, 0)[0], 8);   // 0.4*0 + 0.4*10 + 0.2*20
    EXPECT_EQ(out.at(1, 0)[0], 32);  // 0.2*20 + 0.4*30 + 0.4*40
    EXPECT_EQ(out.at(1, 0)[3], 255);
    // Odd width in side-by-side-half: the left eye gets floor(5 / 2) = 2 columns, the right eye 3.
    const Image sbs = compose(StereoOutput::kSideBySideHalf, src, Image::filled(5, 1, 0, 200, 0, 255));
    EXPECT_EQ(sbs.width, 5);
    EXPECT_EQ(sbs.at(1, 0)[0], 32);
    for (int x = 2; x < 5; ++x) EXPECT_EQ(sbs.at(x, 0)[1], 200);
    EXPECT_THROW(resample_box(src, 0, 1), Error);
    EXPECT_THROW(resample_box(Image{}, 1, 1), Error);
}

TEST(StereoOutput, ColourAndGrayAnaglyphTakeRedFromTheLeftEye) {
    const Image l = Image::filled(2, 2, 200, 100, 50, 255), r = Image::filled(2, 2, 10, 20, 30, 255);
    const Image c = compose(StereoOutput::kAnaglyph, l, r, {.anaglyph = AnaglyphMethod::kColour});
    EXPECT_EQ(c.at(1, 1)[0], 200);
    EXPECT_EQ(c.at(1, 1)[1], 20);
    EXPECT_EQ(c.at(1, 1)[2], 30);
    EXPECT_EQ(c.at(1, 1)[3], 255);
    const Image g = compose(StereoOutput::kAnaglyph, l, r, {.anaglyph = AnaglyphMethod::kGray});
    EXPECT_EQ(g.at(0, 0)[0], 124);  // 0.299*200 + 0.587*100 + 0.114*50 = 59.8 + 58.7 + 5.7 = 124.2 -> 124
    EXPECT_EQ(g.at(0, 0)[1], 18);   // 0.299*10 + 0.587*20 + 0.114*30 = 2.99 + 11.74 + 3.42 = 18.15 -> 18
    EXPECT_EQ(g.at(0, 0)[1], g.at(0, 0)[2]);
    const Image swapped =
        compose(StereoOutput::kAnaglyph, l, r, {.swap_eyes = true, .anaglyph = AnaglyphMethod::kColour});
    EXPECT_EQ(swapped.at(0, 0)[0], 10);
    EXPECT_EQ(swapped.at(0, 0)[1], 100);
}

TEST(StereoOutput, DuboisAnaglyphMatchesTheMatricesInLinearLight) {
    const auto one = [](std::uint8_t lr, std::uint8_t lg, std::uint8_t lb, std::uint8_t rr, std::uint8_t rg,
                        std::uint8_t rb) {
        const Image out =
            compose(StereoOutput::kAnaglyph, Image::filled(1, 1, lr, lg, lb), Image::filled(1, 1, rr, rg, rb));
        return std::array<int, 4>{out.at(0, 0)[0], out.at(0, 0)[1], out.at(0, 0)[2], out.at(0, 0)[3]};
    };
    // Rows of M_L + M_R sum to 1 (to 5e-6): white and black pass unchanged, mid grey 128 stays 128.
    EXPECT_EQ(one(255, 255, 255, 255, 255, 255), (std::array<int, 4>{255, 255, 255, 255}));
    EXPECT_EQ(one(0, 0, 0, 0, 0, 0), (std::array<int, 4>{0, 0, 0, 255}));
    EXPECT_EQ(one(128, 128, 128, 128, 128, 128), (std::array<int, 4>{128, 128, 128, 255}));
    // Left pure red: linear 0.4561 in red -> sRGB 0.7064 -> 180; green and blue negative -> 0.
    EXPECT_EQ(one(255, 0, 0, 0, 0, 0), (std::array<int, 4>{180, 0, 0, 255}));
    // Right pure blue: 1.2264 clipped to 1 in blue; red and green negative -> 0.
    EXPECT_EQ(one(0, 0, 0, 0, 0, 255), (std::array<int, 4>{0, 0, 255, 255}));
}

TEST(StereoOutput, DuboisTableEncodingEqualsDirectSrgbRounding) {
    // Reference: decode with the sRGB formula, mix, clamp, encode with the formula and round to nearest.
    const double ml[3][3] = {{0.456100, 0.500484, 0.176381},
                             {-0.0400822, -0.0378246, -0.0157589},
                             {-0.0152161, -0.0205971, -0.00546856}};
    const double mr[3][3] = {{-0.0434706, -0.0879388, -0.00155529},
                             {0.378476, 0.73364, -0.0184503},
                             {-0.0721527, -0.112961, 1.2264}};
    const auto dec = [](int c8) {
        const double c = c8 / 255.0;
        return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
    };
    const auto enc = [](double v) {
        v = std::clamp(v, 0.0, 1.0);
        const double e = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
        return static_cast<int>(std::lround(255.0 * e));
    };
    constexpr int kSide = 64;  // 4096 pixels of pseudo-random colours
    Image l = Image::filled(kSide, kSide, 0, 0, 0), r = Image::filled(kSide, kSide, 0, 0, 0);
    std::uint32_t state = 12345u;
    for (std::size_t i = 0; i < l.rgba.size(); ++i) {
        if (i % 4 == 3) continue;
        state = state * 1664525u + 1013904223u;
        l.rgba[i] = static_cast<std::uint8_t>(state >> 24);
        state = state * 1664525u + 1013904223u;
        r.rgba[i] = static_cast<std::uint8_t>(state >> 24);
    }
    const Image out = compose(StereoOutput::kAnaglyph, l, r);
    int mismatches = 0;
    for (std::size_t i = 0; i < out.rgba.size(); i += 4) {
        for (int c = 0; c < 3; ++c) {
            double v = 0.0;
            for (int k = 0; k < 3; ++k) v += ml[c][k] * dec(l.rgba[i + k]) + mr[c][k] * dec(r.rgba[i + k]);
            mismatches += out.rgba[i + c] != enc(v);
        }
    }
    EXPECT_EQ(mismatches, 0);
}

TEST(StereoOutput, QuadAndFrameSequentialPickTheSlotsEye) {
    const Image l = coded(3, 2, 1, 7), r = coded(3, 2, 50, 9);
    for (StereoOutput o : {StereoOutput::kQuad, StereoOutput::kFrameSequential}) {
        EXPECT_EQ(compose(o, l, r, {.eye_slot = 0}).rgba, l.rgba);
        EXPECT_EQ(compose(o, l, r, {.eye_slot = 1}).rgba, r.rgba);
        EXPECT_EQ(compose(o, l, r, {.swap_eyes = true, .eye_slot = 0}).rgba, r.rgba);
        EXPECT_EQ(compose(o, l, r, {.swap_eyes = true, .eye_slot = 1}).rgba, l.rgba);
        EXPECT_THROW(compose(o, l, r, {.eye_slot = 2}), Error);
    }
}

TEST(StereoOutput, MonoIsTheOneViewAndIgnoresTheOther) {
    const Image l = coded(3, 2, 1, 7);
    EXPECT_EQ(compose(StereoOutput::kMono, l, Image{}).rgba, l.rgba);
    EXPECT_EQ(compose(StereoOutput::kMono, l, coded(3, 2, 5, 5), {.swap_eyes = true}).rgba, l.rgba);
    EXPECT_THROW(compose(StereoOutput::kMono, Image{}, l), Error);
}

TEST(StereoOutput, BadImagesAreRefused) {
    const Image a = coded(3, 2, 1, 1), b = coded(4, 2, 1, 1);
    for (StereoOutput o : all_stereo_outputs()) {
        if (o == StereoOutput::kMono) continue;
        EXPECT_THROW(compose(o, a, b), Error) << to_string(o);
        EXPECT_THROW(compose(o, a, Image{}), Error) << to_string(o);
    }
    Image broken = a;
    broken.rgba.pop_back();
    EXPECT_THROW(compose(StereoOutput::kAnaglyph, broken, a), Error);
    EXPECT_THROW(compose(StereoOutput::kSideBySideHalf, coded(1, 2, 0, 0), coded(1, 2, 0, 0)), Error);
    EXPECT_THROW(compose(StereoOutput::kTopBottomHalf, coded(2, 1, 0, 0), coded(2, 1, 0, 0)), Error);
}

}  // namespace
}  // namespace tridex::renderer
