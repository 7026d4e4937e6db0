// `tridex replay REC --strip FILE.png`: a recorded carve told in pictures. The strip has the asked number of pictures
// side by side, the first before the tool cut anything and the last after the carve, so the two differ where the
// groove is; the replay's own outputs are still written.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "renderer/image/image.hpp"
#include "test_files.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

// Pixels that differ by more than 24 in a channel between picture a and picture b of a strip of w x h pictures.
std::size_t changed_pixels(const renderer::Image& strip, int a, int b, int w, int h, int gap) {
    std::size_t n = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::uint8_t* p = strip.at(a * (w + gap) + x, y);
            const std::uint8_t* q = strip.at(b * (w + gap) + x, y);
            n += std::abs(p[0] - q[0]) > 24 || std::abs(p[1] - q[1]) > 24 || std::abs(p[2] - q[2]) > 24;
        }
    return n;
}

TEST(FilmStrip, AReplayDrawsTheCarveInPicturesSideBySide) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_film_strip";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string rec = (dir / "carve.trdx").string();
    const auto d = test::run_tridex("demo --seconds 2 --cpu --no-journal --width 64 --height 48 --record " + rec +
                                        " --out " + (dir / "demo").string(),
                                    dir / "demo_log");
    ASSERT_EQ(d.exit_code, 0) << d.err;
    const std::string strip = (dir / "strip.png").string();
    const auto r = test::run_tridex("replay " + rec + " --cpu --validate --width 64 --height 48 --strip " + strip +
                                        " --strip-frames 4 --strip-size 160x120 --out " + (dir / "replay").string(),
                                    dir / "replay_log");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const renderer::Image img = renderer::read_png(strip);
    EXPECT_EQ(img.width, 4 * 160 + 3 * 4);
    EXPECT_EQ(img.height, 120);
    const std::size_t first_last = changed_pixels(img, 0, 3, 160, 120, 4);
    std::printf("[ strip ] %zu px differ between the first and the last picture\n", first_last);
    EXPECT_GT(first_last, 100u) << "the carve does not show: the first and the last picture are alike";
    EXPECT_TRUE(fs::exists(dir / "replay" / "report.json"));
    EXPECT_NE(test::bytes_of(dir / "replay_log" / "stdout.txt").find("film strip: 4 pictures"), std::string::npos);
    // A strip option out of range is refused before any work, naming it.
    const auto bad = test::run_tridex("replay " + rec + " --strip " + strip + " --strip-frames 1 --out " +
                                          (dir / "bad").string(),
                                      dir / "bad_log");
    EXPECT_NE(bad.exit_code, 0);
    EXPECT_NE(bad.err.find("frames must be 2..24"), std::string::npos) << bad.err;
    if (!HasFailure()) fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
