// compute/model/tdx_palette.cpp - the .tdx palette section, encoded and checked.
#include "compute/model/tdx_palette.hpp"

#include <cstdint>
#include <cstring>

#include "core/error.hpp"

namespace tridex::compute::tdx {

Bytes encode_palette(const MaterialPalette& palette) {
    Bytes out;
    const std::uint32_t count = kPaletteSize;
    const auto* c = reinterpret_cast<const unsigned char*>(&count);
    out.insert(out.end(), c, c + 4);
    for (int i = 0; i < kPaletteSize; ++i) {
        const PaletteEntry& e = palette.entries[i];
        out.push_back(static_cast<unsigned char>(i));
        out.push_back(static_cast<unsigned char>(e.name.size()));
        out.insert(out.end(), e.name.begin(), e.name.end());
        const auto* f = reinterpret_cast<const unsigned char*>(e.rgb.data());
        out.insert(out.end(), f, f + 3 * sizeof(float));
    }
    return out;
}

MaterialPalette decode_palette(const unsigned char* data, std::size_t n, const std::string& where) {
    std::size_t at = 0;
    auto need = [&](std::size_t k, const char* what) {
        if (n - at < k) throw Error(where + ": truncated in " + what + " (" + std::to_string(n) + " bytes)");
    };
    need(4, "the entry count");
    std::uint32_t count = 0;
    std::memcpy(&count, data, 4);
    at = 4;
    if (count != static_cast<std::uint32_t>(kPaletteSize))
        throw Error(where + ": " + std::to_string(count) + " entries, expected " + std::to_string(kPaletteSize));
    MaterialPalette p;
    for (int i = 0; i < kPaletteSize; ++i) {
        need(2, "an entry's id");
        if (data[at] != i) throw Error(where + ": entry " + std::to_string(i) + " has id " + std::to_string(data[at]));
        const std::size_t len = data[at + 1];
        at += 2;
        need(len + 3 * sizeof(float), "an entry's name and colour");
        p.entries[i].name.assign(reinterpret_cast<const char*>(data + at), len);
        at += len;
        std::memcpy(p.entries[i].rgb.data(), data + at, 3 * sizeof(float));
        at += 3 * sizeof(float);
    }
    if (at != n) throw Error(where + ": " + std::to_string(n - at) + " bytes after the last entry");
    if (const std::string why = palette_problem(p); !why.empty()) throw Error(where + ": " + why);
    return p;
}

}  // namespace tridex::compute::tdx
