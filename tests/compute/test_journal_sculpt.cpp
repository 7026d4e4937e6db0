// The sculpt thread's journal: it holds exactly the samples the thread applied, in its batches, and applying it
// again (in those batches or any others) gives the same dexels.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <thread>

#include "journal_stream.hpp"
#include "journalled_session.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/journal/journal_writer.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/error.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;


void expect_same_dexels(const compute::TriDexel& a, const compute::TriDexel& b) {
    for (int k = 0; k < 3; ++k) {
        ASSERT_EQ(a.sets[k].rays.size(), b.sets[k].rays.size());
        for (std::size_t r = 0; r < a.sets[k].rays.size(); ++r) {
            const auto& x = a.sets[k].rays[r];
            const auto& y = b.sets[k].rays[r];
            ASSERT_EQ(x.size(), y.size()) << "set " << k << " ray " << r;
            for (std::size_t n = 0; n < x.size(); ++n) {
                ASSERT_TRUE(std::memcmp(&x[n].enter, &y[n].enter, sizeof(float)) == 0 &&
                            std::memcmp(&x[n].exit, &y[n].exit, sizeof(float)) == 0)
                    << "set " << k << " ray " << r << " interval " << n;
                ASSERT_EQ(x[n].enter_material, y[n].enter_material) << "set " << k << " ray " << r;
                ASSERT_EQ(x[n].exit_material, y[n].exit_material) << "set " << k << " ray " << r;
            }
        }
    }
}

TEST(JournalSculpt, TheJournalReplaysToTheSameDexelsInAnyBatches) {
    const std::string path = (fs::temp_directory_path() / ("tridex_journal_sculpt_" + std::to_string(::getpid()) + ".tdj")).string();
    compute::TriDexel live = test::journal_box_model();
    const test::JournalledRun run =
        test::sculpt_journalled(live, test::journal_stream(), path, 11, std::chrono::microseconds(400));
    EXPECT_GT(run.sculpt.busy_ms, 0.0);
    const compute::JournalStats& stats = run.journal;
    EXPECT_EQ(stats.error, "");
    EXPECT_EQ(stats.samples, 450u);
    EXPECT_GE(stats.flushes, 2u);  // the header, and the thread's last sync

    const compute::Journal j = compute::read_journal(path);
    EXPECT_FALSE(j.cut);
    EXPECT_EQ(j.records.size(), stats.records);
    const auto samples = test::journal_stream();
    std::size_t at = 0;
    for (const compute::JournalRecord& r : j.records)
        for (const ToolSample& s : r.samples) {
            ASSERT_LT(at, samples.size());
            EXPECT_EQ(std::memcmp(&s.position, &samples[at].position, sizeof s.position), 0);
            EXPECT_EQ(s.op, samples[at].op);
            ++at;
        }
    EXPECT_EQ(at, samples.size());

    // In the thread's batches.
    compute::TriDexel again = test::journal_box_model();
    const compute::JournalApplyStats st = compute::journal_apply(again, j.records);
    EXPECT_EQ(st.records, j.records.size());
    EXPECT_EQ(st.samples, 450u);
    EXPECT_EQ(st.booleans, 449u);
    EXPECT_DOUBLE_EQ(st.last_t_s, samples.back().t_s);
    expect_same_dexels(live, again);

    // One sample per batch, and everything in one batch: batching does not change the model.
    std::vector<compute::JournalRecord> singles, one(1);
    for (const ToolSample& s : samples) {
        singles.push_back({});
        singles.back().samples.push_back(s);
        one[0].samples.push_back(s);
    }
    compute::TriDexel split = test::journal_box_model(), whole = test::journal_box_model();
    compute::journal_apply(split, singles);
    compute::journal_apply(whole, one);
    expect_same_dexels(live, split);
    expect_same_dexels(live, whole);
    fs::remove(path);
}


// Records as the reader returns them after skipping damage: a gap in the record indices. Stroke 1's end mark was lost,
// so the replay merges strokes 1 and 2; the stroke end the journal calls 2 closes the merged stroke, and the undo
// of stroke 2 then undoes it whole, back to the untouched box. An undo of a stroke the replay does not have is
// skipped and counted, not fatal.
TEST(JournalSculpt, MarksAfterALostStrokeEndAreMatchedLeniently) {
    const std::vector<ToolSample> samples = test::journal_stream();
    std::vector<compute::JournalRecord> r(5);
    r[0].index = 0;  // stroke 1's samples; index 1 (its end mark) is missing
    r[0].samples.assign(samples.begin(), samples.begin() + 150);
    r[1].index = 2;  // stroke 2's samples
    r[1].samples.assign(samples.begin() + 150, samples.begin() + 300);
    r[2].index = 3;
    r[2].kind = compute::JournalKind::kStrokeEnd;
    r[2].serial = 2;
    r[3].index = 4;
    r[3].kind = compute::JournalKind::kUndo;
    r[3].serial = 2;
    r[4].index = 5;
    r[4].kind = compute::JournalKind::kUndo;
    r[4].serial = 9;
    const compute::TriDexel box = test::journal_box_model();
    compute::TriDexel m = test::journal_box_model();
    const compute::JournalApplyStats st = compute::journal_apply(m, r);
    EXPECT_EQ(st.strokes, 1u);
    EXPECT_EQ(st.undos, 1u);
    EXPECT_EQ(st.marks_skipped, 1u);
    EXPECT_EQ(st.samples, 300u);
    expect_same_dexels(box, m);

    // Without the gap the same records are a replay that disagrees with the journal: refused.
    r[1].index = 1;
    r[2].index = 2;
    r[3].index = 3;
    r[4].index = 4;
    compute::TriDexel strict = test::journal_box_model();
    EXPECT_THROW(compute::journal_apply(strict, r), Error);
}

}  // namespace
}  // namespace tridex::app
