// `tridex replay REC --strip FILE.png`: a recorded carve told in pictures. The strip has the asked number of pictures
// side by side, the first before the tool cut anything and the last after the carve, so the two differ where the
// groove is; the replay's own outputs are still written. Where the pictures stop (app/session/report/strip_moments.hpp), on
// made-up journals.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "app/session/report/strip_moments.hpp"
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

// A journal of batches of `samples` samples each (device time 1 ms apart, carving from record `first_op` on) and, at
// the places given, marks with no sample (an undo).
compute::Journal journal_of(int batches, int samples, int first_op, const std::vector<int>& undo_after = {}) {
    compute::Journal j;
    double t = 0.0;
    for (int b = 0; b < batches; ++b) {
        compute::JournalRecord r;
        for (int i = 0; i < samples; ++i) {
            ToolSample s;
            s.t_s = t += 1e-3;
            s.op = b >= first_op ? ToolOp::kSubtract : ToolOp::kNone;
            r.samples.push_back(s);
        }
        j.records.push_back(r);
        for (int u : undo_after)
            if (u == b) {
                compute::JournalRecord mark;
                mark.kind = compute::JournalKind::kUndo;
                j.records.push_back(mark);
            }
    }
    for (std::size_t k = 0; k < j.records.size(); ++k) j.records[k].index = k;
    return j;
}

// The pictures spread over the stretch where the model changed: not over the approach with its graze, not over the
// moving about after the last change; the last just after that change, even when it is a mark (an undo) with no
// sample of its own.
TEST(FilmStrip, PicturesSpreadOverTheStretchWhereTheModelChanged) {
    const compute::Journal j = journal_of(10, 10, 1, {8});  // records 0..8 batches, 9 the undo, 10 a batch
    ASSERT_EQ(j.records.size(), 11u);
    // A graze (0.5 of 100) in record 2, the carve in 4..6, the undo in 9; nothing after.
    const std::vector<double> change{0, 0, 0.5, 0, 30, 30, 30, 0, 0, 9.5, 0};
    EXPECT_EQ(strip_picture_records(j, change, 4), (std::vector<std::size_t>{4, 6, 8, 10}));
    EXPECT_EQ(strip_picture_records(j, change, 2), (std::vector<std::size_t>{4, 10}));
    // Nothing changed: from the first sample with an operation to the end, evenly.
    const std::vector<std::size_t> none = strip_picture_records(j, std::vector<double>(11, 0.0), 3);
    EXPECT_EQ(none.front(), 1u);
    EXPECT_EQ(none.back(), 11u);
}

TEST(FilmStrip, BigBatchesAreSplitIntoPiecesAPictureCanStopBetween) {
    const compute::Journal j = journal_of(2, 20, 0, {0});  // 20 samples, the undo, 20 samples
    const compute::Journal fine = split_batches(j, 8);
    ASSERT_EQ(fine.records.size(), 7u);  // 8 + 8 + 4, the undo, 8 + 8 + 4
    EXPECT_EQ(fine.records[2].samples.size(), 4u);
    EXPECT_EQ(fine.records[3].kind, compute::JournalKind::kUndo);
    for (std::size_t k = 0; k < fine.records.size(); ++k) EXPECT_EQ(fine.records[k].index, k);
    EXPECT_EQ(fine.records[4].samples.front().t_s, j.records[2].samples.front().t_s);
    EXPECT_EQ(fine.records[6].samples.back().t_s, j.records[2].samples.back().t_s);
}

}  // namespace
}  // namespace tridex::app
