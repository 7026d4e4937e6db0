// The wall's first minutes (README, "The wall in five minutes"): the wall scene, with the README's display config,
// shows the workpiece where a standing person's hands are, in front of the screen; the desk's default scene, whose
// workpiece sits at floor height in the wall's frame, shows an empty wall.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "../test_paths.hpp"
#include "renderer/image/image.hpp"
#include "test_files.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

// The share of the image's pixels, below the overlay's corner, that differ from the background (the bottom-left
// pixel) by more than 24 in a channel: what the scene drew.
double drawn_share(const renderer::Image& img) {
    const std::uint8_t* bg = img.rgba.data() + (static_cast<std::size_t>(img.height - 1) * img.width) * 4;
    std::size_t drawn = 0, counted = 0;
    for (int y = img.height / 8; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const std::uint8_t* p = img.rgba.data() + (static_cast<std::size_t>(y) * img.width + x) * 4;
            ++counted;
            drawn += std::abs(p[0] - bg[0]) > 24 || std::abs(p[1] - bg[1]) > 24 || std::abs(p[2] - bg[2]) > 24;
        }
    return static_cast<double>(drawn) / static_cast<double>(counted);
}

double wall_share(const std::string& scene, const fs::path& out) {
    const std::string config = std::string(TRIDEX_ASSETS_DIR) + "/dtrack_powerwall_display.json";
    const auto r = test::run_tridex("run " + scene + " --display offscreen --display-config " + config +
                                        " --stereo mono --frames 2 --no-journal --cpu --out " + out.string(),
                                    out.string() + "_log");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return drawn_share(renderer::read_png((out / "left.png").string()));
}

TEST(WallScene, ShowsTheWorkpieceInFrontOfTheWallAtHandHeight) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_wall_scene";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const double wall = wall_share(std::string(TRIDEX_ASSETS_DIR) + "/wall_scene.json", dir / "wall");
    const double desk = wall_share("", dir / "desk");
    std::printf("[ wall ] pixels drawn: wall scene %.2f %%, desk scene on the wall %.2f %%\n", 100.0 * wall, 100.0 * desk);
    EXPECT_GT(wall, 0.02) << "the wall scene's workpiece is not on the wall";
    EXPECT_LT(desk, 0.001) << "the desk scene on the wall was expected empty (floor height): the test would not fail";
    fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
