// tests/compute/test_tdx_palette.cpp - the .tdx palette section: a custom palette round trips bit for bit (format
// version 2), a default palette is saved as version 1 (what older readers read) and loads as the default, and a
// damaged palette payload is refused with a message naming what is wrong.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "compute/model/tdx_file.hpp"
#include "compute/model/tdx_palette.hpp"
#include "core/error.hpp"
#include "tdx_test_models.hpp"

using namespace tridex;
using namespace tridex::compute;
namespace fs = std::filesystem;
using tdx::Bytes;

namespace {

constexpr std::size_t kBudget = std::size_t{1} << 30;

fs::path temp_dir() {
    const fs::path d = fs::temp_directory_path() / ("tridex_tdx_palette_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
}

std::vector<unsigned char> read_all(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), {}};
}

std::uint32_t get32(const std::vector<unsigned char>& b, std::size_t at) {
    std::uint32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;
}

MaterialPalette custom_palette() {
    MaterialPalette p = default_material_palette();
    p.entries[1] = {"teal", rgb_from_srgb8({0x2a, 0x9d, 0x8f})};
    p.entries[2] = {"sand_2", rgb_from_srgb8({0xe9, 0xc4, 0x6a})};
    p.entries[0].rgb = {0.5f, 0.25f, 0.125f};
    return p;
}

std::string decode_error(const Bytes& b) {
    try {
        (void)tdx::decode_palette(b.data(), b.size(), "p.tdx: section 'palette'");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(TdxPalette, ACustomPaletteRoundTripsBitForBitAsVersion2) {
    const TriDexel m = tdx_test::sculpted_sphere(32, 40, 5u);
    const MaterialPalette palette = custom_palette();
    const fs::path a = temp_dir() / "a.tdx", b = temp_dir() / "b.tdx";
    save_tdx(a.string(), m, Mat4(1.0), R"({"resolution": 32})", 3, palette);
    const std::vector<unsigned char> bytes = read_all(a);
    EXPECT_EQ(get32(bytes, 8), 2u);   // version
    EXPECT_EQ(get32(bytes, 16), 7u);  // sections
    const TdxModel loaded = load_tdx(a.string(), kBudget);
    EXPECT_EQ(loaded.palette, palette);
    EXPECT_EQ(loaded.settings_json, R"({"resolution": 32})");
    save_tdx(b.string(), loaded.model, loaded.to_world, loaded.settings_json, 3, loaded.palette);
    EXPECT_EQ(read_all(b), bytes);  // load -> save gives the same bytes
    EXPECT_EQ(load_tdx_palette(a.string()), palette);  // the palette alone, the rest skipped
}

TEST(TdxPalette, TheDefaultPaletteIsSavedAsVersion1AndOldFilesLoadWithIt) {
    const TriDexel m = tdx_test::sculpted_sphere(24, 20, 7u);
    const fs::path a = temp_dir() / "v1.tdx";
    save_tdx(a.string(), m, Mat4(1.0), "{}");  // the version 1 layout: six sections, no palette
    const std::vector<unsigned char> bytes = read_all(a);
    EXPECT_EQ(get32(bytes, 8), 1u);
    EXPECT_EQ(get32(bytes, 16), 6u);
    const TdxModel loaded = load_tdx(a.string(), kBudget);
    EXPECT_EQ(loaded.palette, default_material_palette());
    EXPECT_EQ(load_tdx_palette(a.string()), default_material_palette());
    // A version 2 header that claims only six sections is refused (the palette is missing).
    std::vector<unsigned char> v2 = bytes;
    v2[8] = 2;
    std::ofstream(a, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(v2.data()),
                                                               static_cast<std::streamsize>(v2.size()));
    EXPECT_THROW((void)load_tdx(a.string(), kBudget), Error);
}

TEST(TdxPalette, DamagedPalettesAreRefusedNamingTheFault) {
    const Bytes good = tdx::encode_palette(custom_palette());
    EXPECT_EQ(decode_error(good), "");
    EXPECT_EQ(tdx::decode_palette(good.data(), good.size(), "x"), custom_palette());
    Bytes b = good;
    b[0] = 9;  // count
    EXPECT_NE(decode_error(b).find("9 entries, expected 8"), std::string::npos) << decode_error(b);
    b = good;
    b.push_back(0);
    EXPECT_NE(decode_error(b).find("1 bytes after the last entry"), std::string::npos) << decode_error(b);
    b.assign(good.begin(), good.end() - 3);
    EXPECT_NE(decode_error(b).find("truncated"), std::string::npos) << decode_error(b);
    MaterialPalette twice = custom_palette();
    twice.entries[3].name = "teal";
    b = tdx::encode_palette(twice);
    EXPECT_NE(decode_error(b).find("material 3: the name 'teal' is already material 1's"), std::string::npos)
        << decode_error(b);
    MaterialPalette bright = custom_palette();
    bright.entries[4].rgb[1] = 1.5f;
    b = tdx::encode_palette(bright);
    EXPECT_NE(decode_error(b).find("material 4: a colour component must be in [0, 1]"), std::string::npos);
    MaterialPalette spaced = custom_palette();
    spaced.entries[5].name = "deep sea";
    b = tdx::encode_palette(spaced);
    EXPECT_NE(decode_error(b).find("only letters, digits"), std::string::npos);
    EXPECT_THROW(save_tdx((temp_dir() / "bad.tdx").string(), tdx_test::sculpted_sphere(16, 4, 1u), Mat4(1.0), "{}", 3,
                          twice),
                 Error);
}
