// core/material_palette.hpp - the session's materials as people name and see them: one name and one colour per
// material id (0 = the workpiece's own material, 1..kMaxMaterialId the ones union adds and paint sets). The scene
// names them, the model file (.tdx) and the session spec keep them, the renderer draws from them and export writes
// them, so the type lives here, free of Vulkan and of any file format.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "core/tool_sample.hpp"

namespace tridex {

/// Number of palette entries: one per material id 0..kMaxMaterialId.
inline constexpr int kPaletteSize = kMaxMaterialId + 1;
/// Longest material name, bytes.
inline constexpr std::size_t kMaterialNameMax = 32;

/// One material's name and colour.
struct PaletteEntry {
    std::string name;                  ///< 1..kMaterialNameMax of [A-Za-z0-9_-], unique in its palette
    /// The colour as the renderer takes it: sRGB-encoded RGB in [0, 1] ("#2a9d8f" = 42/255, 157/255, 143/255). The
    /// stereo renderer lights it as it is and writes the result to an 8-bit UNORM target without encoding, so a
    /// surface lit at full strength shows exactly this colour, and PNG pictures, PLY colours and the scene agree.
    std::array<float, 3> rgb{};
    bool operator==(const PaletteEntry&) const = default;
};

/// The colours and names of material ids 0..kMaxMaterialId; always full (a scene renames or recolours some entries,
/// the others keep the default's).
struct MaterialPalette {
    std::array<PaletteEntry, kPaletteSize> entries;
    bool operator==(const MaterialPalette&) const = default;
    /// The entry of material `id` (0..kMaxMaterialId; ids beyond are clamped to 0, the workpiece's own).
    const PaletteEntry& operator[](int id) const { return entries[id >= 0 && id < kPaletteSize ? id : 0]; }
    /// The id of the entry named `name` (exact match), or -1.
    int find(const std::string& name) const;
};

/// The palette every session had before palettes were named: 0 clay (0.80, 0.62, 0.45), 1 red, 2 green,
/// 3 blue, 4 yellow, 5 white, 6 charcoal, 7 purple (the renderer's look is unchanged by it).
const MaterialPalette& default_material_palette();

/// A colour component in [0, 1] (clamped; NaN reads as 0) as 8 bits, rounded to nearest.
std::uint8_t to_byte(float c);
/// An entry's colour as 8-bit sRGB (to_byte of each component).
std::array<std::uint8_t, 3> srgb8(const PaletteEntry& e);
/// The palette colour of 8-bit sRGB `rgb` (each / 255; srgb8 gives the bytes back exactly).
std::array<float, 3> rgb_from_srgb8(const std::array<std::uint8_t, 3>& rgb);
/// 8-bit sRGB -> linear light in [0, 1] (IEC 61966-2-1), for tools that want linear values.
float srgb8_to_linear(std::uint8_t c);

/// Parses "#rrggbb" (hex digits, either case) into 8-bit sRGB; returns false (leaving `out` alone) on anything else.
bool parse_hex_colour(const std::string& text, std::array<std::uint8_t, 3>& out);
/// "#rrggbb" (lower case) of 8-bit sRGB `rgb`.
std::string hex_colour(const std::array<std::uint8_t, 3>& rgb);

/// Why `name` cannot name a material ("" when it can): empty, longer than kMaterialNameMax, or a byte outside
/// [A-Za-z0-9_-] (names become OBJ material names and menu labels, which take no spaces).
std::string material_name_problem(const std::string& name);
/// Why `palette` is not valid ("" when it is): the first entry with a bad name, a name used twice, or a colour
/// component not finite or outside [0, 1], e.g. "material 3: the name 'red' is already material 1's".
std::string palette_problem(const MaterialPalette& palette);

}  // namespace tridex
