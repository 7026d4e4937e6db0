// tests/core/test_material_palette.cpp - the palette type: the default names and colours, sRGB <-> linear, "#rrggbb"
// parsing and the checks on names and colours.
#include <gtest/gtest.h>

#include <limits>

#include "core/material_palette.hpp"

namespace tridex {
namespace {

TEST(MaterialPalette, TheDefaultKeepsTheColoursSessionsAlwaysHadWithNames) {
    const MaterialPalette& p = default_material_palette();
    EXPECT_EQ(p[0].name, "clay");
    EXPECT_EQ(p[0].rgb, (std::array<float, 3>{0.80f, 0.62f, 0.45f}));
    EXPECT_EQ(p[1].name, "red");
    EXPECT_EQ(p[7].name, "purple");
    EXPECT_EQ(p.find("charcoal"), 6);
    EXPECT_EQ(p.find("Charcoal"), -1);
    EXPECT_EQ(&p[99], &p[0]);  // out of range reads as the workpiece's own
    EXPECT_EQ(palette_problem(p), "");
}

TEST(MaterialPalette, BytesAndColoursConvertBothWaysExactly) {
    for (int c = 0; c < 256; ++c) {
        const auto b = static_cast<std::uint8_t>(c);
        const PaletteEntry e{"x", rgb_from_srgb8({b, b, b})};
        EXPECT_EQ(srgb8(e), (std::array<std::uint8_t, 3>{b, b, b})) << c;
    }
    EXPECT_EQ(to_byte(-1.0f), 0);
    EXPECT_EQ(to_byte(7.0f), 255);
    EXPECT_EQ(to_byte(std::numeric_limits<float>::quiet_NaN()), 0);
    // Clay as the renderer writes it lit at full strength, and as PLY and the PNG pictures show it.
    EXPECT_EQ(hex_colour(srgb8(default_material_palette()[0])), "#cc9e73");
    EXPECT_EQ(srgb8_to_linear(0), 0.0f);
    EXPECT_EQ(srgb8_to_linear(255), 1.0f);
    EXPECT_NEAR(srgb8_to_linear(128), 0.2158605f, 1e-6);
}

TEST(MaterialPalette, HexColoursParseStrictly) {
    std::array<std::uint8_t, 3> rgb{1, 2, 3};
    EXPECT_TRUE(parse_hex_colour("#2a9D8f", rgb));
    EXPECT_EQ(rgb, (std::array<std::uint8_t, 3>{0x2a, 0x9d, 0x8f}));
    EXPECT_EQ(hex_colour(rgb), "#2a9d8f");
    for (const char* bad : {"2a9d8f", "#2a9d8", "#2a9d8f0", "#2a9g8f", "", "#"}) {
        std::array<std::uint8_t, 3> keep{1, 2, 3};
        EXPECT_FALSE(parse_hex_colour(bad, keep)) << bad;
        EXPECT_EQ(keep, (std::array<std::uint8_t, 3>{1, 2, 3}));
    }
}

TEST(MaterialPalette, NamesAndColoursAreChecked) {
    EXPECT_EQ(material_name_problem("deep_sea-2"), "");
    EXPECT_NE(material_name_problem(""), "");
    EXPECT_NE(material_name_problem("deep sea").find("only letters, digits"), std::string::npos);
    EXPECT_NE(material_name_problem(std::string(33, 'a')).find("at most 32"), std::string::npos);
    MaterialPalette p = default_material_palette();
    p.entries[4].name = "red";
    EXPECT_EQ(palette_problem(p), "material 4: the name 'red' is already material 1's");
    p = default_material_palette();
    p.entries[2].rgb[2] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(palette_problem(p), "material 2: a colour component must be in [0, 1]");
}

}  // namespace
}  // namespace tridex
