// The wall's test pattern (`tridex run --test-pattern`, docs/wall.md): its pieces lie on the screen the display
// config measured, and rendered through the wall's display each eye's image shows its own label only, so a person
// with one eye closed can tell whether the eyes reach the right shutters.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "../test_paths.hpp"
#include "app/scene/test_pattern.hpp"
#include "core/error.hpp"
#include "renderer/image/image.hpp"
#include "test_files.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

TEST(WallPattern, PiecesLieOnTheScreenAndEachEyeHasItsLabel) {
    const renderer::Screen s = renderer::Screen::powerwall();
    const std::vector<PatternPiece> pieces = wall_test_pattern(s);
    ASSERT_EQ(pieces.size(), 6u);
    int left_only = 0, right_only = 0, in_front = 0, behind = 0;
    for (const PatternPiece& p : pieces) {
        ASSERT_FALSE(p.mesh.triangles.empty());
        left_only += p.eyes == 0b01;
        right_only += p.eyes == 0b10;
        const Aabb b = p.mesh.bounds();
        // The wall's screen is the z = 0 plane facing +z, from x -1.524 to 1.524 m and y -1.143 to 1.143 m.
        EXPECT_GE(b.lo.x, -1.524 - 1e-9);
        EXPECT_LE(b.hi.x, 1.524 + 1e-9);
        EXPECT_GE(b.lo.y, -1.143 - 1e-9);
        EXPECT_LE(b.hi.y, 1.143 + 1e-9);
        if (b.lo.z > 0.1) ++in_front;
        else if (b.hi.z < -0.1) ++behind;
        else EXPECT_LE(std::max(std::abs(b.lo.z), std::abs(b.hi.z)), 0.002 + 1e-12) << "a flat piece off the screen";
    }
    EXPECT_EQ(left_only, 1);
    EXPECT_EQ(right_only, 1);
    EXPECT_EQ(in_front, 1);
    EXPECT_EQ(behind, 1);
    EXPECT_THROW(wall_test_pattern(renderer::Screen{}), Error);
}

// Pixels of the left label's colour (red) and of the right label's (cyan) in the upper 60% of an image (the labels
// straddle the screen's middle; the cubes stand lower).
struct LabelPixels {
    std::size_t red = 0, cyan = 0;
};
LabelPixels label_pixels(const renderer::Image& img) {
    LabelPixels n;
    for (int y = 0; y < img.height * 6 / 10; ++y)
        for (int x = 0; x < img.width; ++x) {
            const std::uint8_t* p = img.at(x, y);
            n.red += p[0] > 150 && p[1] < 130 && p[2] < 130;
            n.cyan += p[0] < 130 && p[1] > 150 && p[2] > 150;
        }
    return n;
}

TEST(WallPattern, EachEyeSeesOnlyItsOwnLabelOnTheWall) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_wall_pattern";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string assets = TRIDEX_ASSETS_DIR;
    const auto r = test::run_tridex("run " + assets + "/wall_scene.json --display offscreen --display-config " + assets +
                                        "/dtrack_powerwall_display.json --test-pattern --stereo side-by-side --frames 2 "
                                        "--cpu --validate --out " + (dir / "out").string(),
                                    dir / "log");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const LabelPixels left = label_pixels(renderer::read_png((dir / "out" / "left.png").string()));
    const LabelPixels right = label_pixels(renderer::read_png((dir / "out" / "right.png").string()));
    std::printf("[ pattern ] left eye: %zu red, %zu cyan px; right eye: %zu red, %zu cyan px\n", left.red, left.cyan,
                right.red, right.cyan);
    EXPECT_GT(left.red, 500u) << "LEFT EYE is missing from the left eye's image";
    EXPECT_EQ(left.cyan, 0u) << "RIGHT EYE shows in the left eye's image";
    EXPECT_GT(right.cyan, 500u) << "RIGHT EYE is missing from the right eye's image";
    EXPECT_EQ(right.red, 0u) << "LEFT EYE shows in the right eye's image";
    const nlohmann::json rep = test::read_json(dir / "out" / "report.json");
    EXPECT_EQ(rep["validation_messages"], 0);
    // A test pattern carves nothing and writes only its images and report: no mesh, no journal.
    EXPECT_FALSE(fs::exists(dir / "out" / "sculpted.ply"));
    EXPECT_FALSE(fs::exists(dir / "out" / "session.tdj"));
    EXPECT_EQ(rep["volume_after_m3"], rep["volume_before_m3"]);
    if (!HasFailure()) fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
