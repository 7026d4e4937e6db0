// compute/model/tdx_palette.hpp - the "palette" section of a .tdx model file (tdx_file.hpp, format version 2): the
// materials' names and colours (core/material_palette.hpp), encoded to bytes and decoded with every value checked.
#pragma once

#include <cstddef>
#include <string>

#include "compute/model/tdx_codec.hpp"
#include "core/material_palette.hpp"

namespace tridex::compute::tdx {

/// Most bytes an encoded palette takes: a u32 count, then per entry a u8 id, a u8 name length, the name and three
/// f32 (MaterialPalette's sRGB-encoded rgb).
inline constexpr std::size_t kPaletteBytesMax = 4 + kPaletteSize * (2 + kMaterialNameMax + 3 * 4);

/// Encodes `palette`: u32 kPaletteSize, then per entry in id order u8 id, u8 name length, the name's bytes and its
/// colour (PaletteEntry::rgb) as 3 f32 (copied bit for bit).
Bytes encode_palette(const MaterialPalette& palette);
/// Decodes and checks a "palette" payload: the count kPaletteSize, ids 0..kPaletteSize-1 in order, the exact size,
/// and palette_problem (names valid and unique, colours finite in [0, 1]). Throws tridex::Error "<where>: ...".
MaterialPalette decode_palette(const unsigned char* data, std::size_t n, const std::string& where);

}  // namespace tridex::compute::tdx
