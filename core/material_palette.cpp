// core/material_palette.cpp - the default palette, sRGB conversions and palette checks.
#include "core/material_palette.hpp"

#include <algorithm>
#include <cmath>

namespace tridex {

int MaterialPalette::find(const std::string& name) const {
    for (int i = 0; i < kPaletteSize; ++i)
        if (entries[i].name == name) return i;
    return -1;
}

const MaterialPalette& default_material_palette() {
    static const MaterialPalette palette{{{
        {"clay", {0.80f, 0.62f, 0.45f}},
        {"red", {0.78f, 0.20f, 0.18f}},
        {"green", {0.25f, 0.62f, 0.30f}},
        {"blue", {0.22f, 0.40f, 0.80f}},
        {"yellow", {0.90f, 0.78f, 0.25f}},
        {"white", {0.92f, 0.92f, 0.90f}},
        {"charcoal", {0.18f, 0.18f, 0.20f}},
        {"purple", {0.58f, 0.32f, 0.70f}},
    }}};
    return palette;
}

std::uint8_t to_byte(float c) {
    const double v = c >= 0.0f ? std::min(static_cast<double>(c), 1.0) : 0.0;  // NaN fails c >= 0
    return static_cast<std::uint8_t>(std::lround(255.0 * v));
}

std::array<std::uint8_t, 3> srgb8(const PaletteEntry& e) { return {to_byte(e.rgb[0]), to_byte(e.rgb[1]), to_byte(e.rgb[2])}; }

std::array<float, 3> rgb_from_srgb8(const std::array<std::uint8_t, 3>& rgb) {
    return {rgb[0] / 255.0f, rgb[1] / 255.0f, rgb[2] / 255.0f};
}

float srgb8_to_linear(std::uint8_t c) {
    const double s = c / 255.0;
    return static_cast<float>(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
}

bool parse_hex_colour(const std::string& text, std::array<std::uint8_t, 3>& out) {
    if (text.size() != 7 || text[0] != '#') return false;
    auto digit = [](char c) -> int {
        if (c >= '0' && c <= '9') return c - '0';
        if (c >= 'a' && c <= 'f') return c - 'a' + 10;
        if (c >= 'A' && c <= 'F') return c - 'A' + 10;
        return -1;
    };
    std::array<std::uint8_t, 3> rgb{};
    for (int k = 0; k < 3; ++k) {
        const int hi = digit(text[1 + 2 * k]), lo = digit(text[2 + 2 * k]);
        if (hi < 0 || lo < 0) return false;
        rgb[k] = static_cast<std::uint8_t>(hi * 16 + lo);
    }
    out = rgb;
    return true;
}

std::string hex_colour(const std::array<std::uint8_t, 3>& rgb) {
    static const char* kDigits = "0123456789abcdef";
    std::string s = "#";
    for (std::uint8_t c : rgb) {
        s += kDigits[c >> 4];
        s += kDigits[c & 15];
    }
    return s;
}

std::string material_name_problem(const std::string& name) {
    if (name.empty()) return "a material name must not be empty";
    if (name.size() > kMaterialNameMax)
        return "a material name has at most " + std::to_string(kMaterialNameMax) + " characters, got " +
               std::to_string(name.size());
    for (char c : name) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
        if (!ok) return "a material name takes only letters, digits, '_' and '-', got '" + name + "'";
    }
    return "";
}

std::string palette_problem(const MaterialPalette& palette) {
    for (int i = 0; i < kPaletteSize; ++i) {
        const PaletteEntry& e = palette.entries[i];
        const std::string where = "material " + std::to_string(i) + ": ";
        if (const std::string why = material_name_problem(e.name); !why.empty()) return where + why;
        const int first = palette.find(e.name);
        if (first != i)
            return where + "the name '" + e.name + "' is already material " + std::to_string(first) + "'s";
        for (float c : e.rgb)
            if (!(c >= 0.0f && c <= 1.0f)) return where + "a colour component must be in [0, 1]";
    }
    return "";
}

}  // namespace tridex
