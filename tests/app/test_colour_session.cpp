// A painted session with colours of the scene's own, end to end through the `tridex` executable: `tridex run` paints
// the bunny teal, the picture it writes shows teal where the tool painted, the saved model and the recording keep
// the palette, and `tridex replay` draws with it and sculpts the same model byte for byte.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "compute/model/tdx_file.hpp"
#include "core/material_palette.hpp"
#include "renderer/image/image.hpp"
#include "test_files.hpp"

namespace {

using tridex::app::test::run_tridex;
namespace fs = std::filesystem;

std::string bytes_of(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

nlohmann::json report(const fs::path& dir) {
    std::ifstream f(dir / "report.json");
    return nlohmann::json::parse(f);
}

// Pixels whose hue is the scene's teal (#2a9d8f, hue 173 degrees) and that are saturated: lit teal, not the bone
// workpiece (hue 40), the grey background or the tool.
std::size_t teal_pixels(const tridex::renderer::Image& img) {
    std::size_t n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const std::uint8_t* p = &img.rgba[static_cast<std::size_t>(4 * (y * img.width + x))];
            const int r = p[0], g = p[1], b = p[2];
            const int mx = std::max({r, g, b}), mn = std::min({r, g, b});
            if (mx < 40 || mx - mn < 0.4 * mx) continue;  // dark or unsaturated
            double h = 0.0;
            if (mx == g) h = 60.0 * (2.0 + static_cast<double>(b - r) / (mx - mn));
            else if (mx == b) h = 60.0 * (4.0 + static_cast<double>(r - g) / (mx - mn));
            else continue;
            n += std::fabs(h - 173.0) < 15.0;
        }
    return n;
}

const char* kScene = R"({
  "workpiece": { "resolution": 64, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.008 },
  "op": "paint", "material": "teal",
  "materials": [{ "id": 0, "name": "bone", "colour": "#f0e6d2" }, { "id": 2, "name": "teal", "colour": "#2a9d8f" }],
  "stroke": { "duration_s": 1.0, "length_m": 0.07, "depth_m": 0.006 },
  "display": { "preset": "desktop", "stereo": "mono", "resolution": [240, 180], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.05, 0.6] }
})";

TEST(ColourSession, APaintedSessionShowsTheScenesColourAndKeepsItEverywhere) {
    const fs::path dir = fs::temp_directory_path() / ("tridex-test-colour-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const char* assets = std::getenv("TRIDEX_ASSETS");
    nlohmann::json scene = nlohmann::json::parse(kScene);
    scene["workpiece"]["mesh"] = (fs::path(assets ? assets : "assets") / "bunny.off").string();
    std::ofstream(dir / "scene.json") << scene.dump(2);
    const fs::path rec = dir / "paint.trdx", model = dir / "painted.tdx";
    const auto live = run_tridex("run " + (dir / "scene.json").string() + " --display offscreen --cpu --record " +
                                     rec.string() + " --save " + model.string() + " --out " + (dir / "live").string(),
                                 dir / "live");
    ASSERT_EQ(live.exit_code, 0) << live.err;
    // The picture: teal where the tool painted.
    const tridex::renderer::Image img = tridex::renderer::read_png((dir / "live" / "output.png").string());
    const std::size_t teal = teal_pixels(img);
    std::printf("output.png %d x %d: %zu teal pixels\n", img.width, img.height, teal);
    EXPECT_GT(teal, 100u);
    // The report's settings, the saved model and the recording keep the palette.
    const nlohmann::json j = report(dir / "live");
    ASSERT_TRUE(j["settings"].contains("palette")) << j["settings"].dump();
    EXPECT_EQ(j["settings"]["palette"][2]["name"], "teal");
    const tridex::compute::TdxModel saved = tridex::compute::load_tdx(model.string(), std::size_t{1} << 30);
    EXPECT_EQ(saved.palette[2].name, "teal");
    EXPECT_EQ(tridex::hex_colour(tridex::srgb8(saved.palette[2])), "#2a9d8f");
    EXPECT_EQ(tridex::hex_colour(tridex::srgb8(saved.palette[0])), "#f0e6d2");
    // The replay: the same model byte for byte, drawn with the recorded palette.
    const auto again = run_tridex("replay " + rec.string() + " --cpu --width 240 --height 180 --out " +
                                      (dir / "replay").string(),
                                  dir / "replay");
    ASSERT_EQ(again.exit_code, 0) << again.err;
    EXPECT_EQ(report(dir / "replay")["settings"]["palette"], j["settings"]["palette"]);
    const std::string a = bytes_of(dir / "live" / "sculpted.ply"), b = bytes_of(dir / "replay" / "sculpted.ply");
    ASSERT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == b) << "the replay painted a different model";
    const std::size_t replay_teal = teal_pixels(tridex::renderer::read_png((dir / "replay" / "left.png").string()));
    std::printf("replay left.png: %zu teal pixels\n", replay_teal);
    EXPECT_GT(replay_teal, 100u);
    if (!HasFailure()) fs::remove_all(dir);
}

}  // namespace
