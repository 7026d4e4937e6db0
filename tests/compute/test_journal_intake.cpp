// The journal's intake: samples journalled as they leave the haptic loop, before the sculpt thread applies them. The
// reader turns those no batch record holds into the journal's tail, which a replay applies as the sculpt thread
// would; a session whose sculpt thread is behind keeps what it received.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>
#include <utility>

#include "journal_stream.hpp"
#include "compute/journal/journal_format.hpp"
#include "compute/journal/journal_intake.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/journal/journal_writer.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/runtime/sculpt_thread.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

std::string temp_path(const std::string& name) {
    return (fs::temp_directory_path() / ("tridex_intake_" + std::to_string(::getpid()) + "_" + name)).string();
}

std::vector<unsigned char> file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}


std::span<const ToolSample> part(const std::vector<ToolSample>& v, std::size_t begin, std::size_t end) {
    return std::span<const ToolSample>(v).subspan(begin, end - begin);
}

// Whether the journal's batches, then its tail, hold exactly samples [0, n) of `all`, in order.
void expect_prefix(const compute::Journal& j, const std::vector<ToolSample>& all, std::size_t& n) {
    n = 0;
    for (const compute::JournalRecord& r : j.records)
        for (const ToolSample& s : r.samples) {
            ASSERT_LT(n, all.size());
            ASSERT_EQ(s.t_s, all[n].t_s) << "sample " << n << " out of place";
            ++n;
        }
}

TEST(JournalIntake, TheTailIsTheIntakeSamplesThatFollowTheBatchesWithoutAGap) {
    const std::vector<ToolSample> s = test::journal_stream();
    const std::string path = temp_path("tail.tdj");
    {
        compute::JournalWriter w(path, "session");
        w.append(part(s, 0, 20));
        w.intake(10, part(s, 10, 40));  // 10..19 are in the batch already: only 20..39 are written
        w.intake(45, part(s, 45, 50));  // 40..44 never arrived: not part of the tail
        w.intake(0, part(s, 0, 5));     // all in the batch: nothing written
        EXPECT_EQ(w.stats().intake_records, 2u);
        EXPECT_EQ(w.stats().intake_samples, 25u);
        EXPECT_EQ(w.stats().samples, 20u);
    }
    const compute::Journal j = compute::read_journal(path);
    EXPECT_EQ(j.version, compute::kJournalVersion);
    ASSERT_EQ(j.records.size(), 4u);  // the batch, two intake records, the tail
    EXPECT_EQ(j.records[1].kind, compute::JournalKind::kIntake);
    EXPECT_TRUE(j.records[1].samples.empty());
    const compute::JournalRecord& tail = j.records.back();
    EXPECT_TRUE(tail.tail);
    EXPECT_EQ(tail.kind, compute::JournalKind::kBatch);
    EXPECT_EQ(tail.index, 3u);
    EXPECT_EQ(j.intake_samples, 25u);
    EXPECT_EQ(j.tail_samples, 20u);
    EXPECT_EQ(j.samples, 40u);
    EXPECT_EQ(j.tail_unplaced, 0u);  // a gap in the intake's numbers is not damage: 45..49 are simply not the tail
    std::size_t n = 0;
    expect_prefix(j, s, n);
    EXPECT_EQ(n, 40u);
    fs::remove(path);
}

TEST(JournalIntake, ATailAfterDamageIsNotApplied) {
    const std::vector<ToolSample> s = test::journal_stream();
    const std::string path = temp_path("damaged.tdj");
    {
        compute::JournalWriter w(path, "session");
        w.append(part(s, 0, 20));
        w.append(part(s, 20, 30));
        w.append(part(s, 30, 40));
        w.intake(40, part(s, 40, 60));
    }
    std::vector<unsigned char> b = file_bytes(path);
    // A bit flipped in the second batch: its samples' count is lost, so the tail's numbering is unknown.
    const std::size_t second = b.size() - (2 * (8 + 16 + 10 * 120 + 4)) - (8 + 24 + 20 * 120 + 4) + 40;
    b[second] ^= 0x10;
    const compute::Journal j = compute::parse_journal(b, "damaged.tdj");
    ASSERT_EQ(j.damage.size(), 1u);
    EXPECT_EQ(j.tail_samples, 0u);
    EXPECT_FALSE(j.records.back().tail);
    EXPECT_EQ(j.damage[0].samples_lost, 10u);
    EXPECT_EQ(j.tail_unplaced, 20u);  // 40..59: past the 30 batch samples kept and the 10 lost
    fs::remove(path);
}

// Batches of 0..19, 20..29 and 30..39, the middle one damaged, after an intake record of 20..intake_end written while
// the sculpt thread was behind: the journal as read.
compute::Journal damaged_after_intake(const std::vector<ToolSample>& s, std::size_t intake_end,
                                      const std::string& name) {
    const std::string path = temp_path(name);
    {
        compute::JournalWriter w(path, "session");
        w.append(part(s, 0, 20));
        w.intake(20, part(s, 20, intake_end));
        w.append(part(s, 20, 30));
        w.append(part(s, 30, 40));
    }
    std::vector<unsigned char> b = file_bytes(path);
    b[b.size() - 2 * (8 + 16 + 10 * 120 + 4) + 40] ^= 0x10;  // a bit flipped in the batch of 20..29
    fs::remove(path);
    return compute::parse_journal(b, name);
}

// Intake whose samples the batches after it hold (the sculpt thread was behind, then caught up): its end (40) is past
// the 30 batch samples kept, not past the 10 more the damaged stretch is estimated to hold, so no tail is unplaced and
// recovery has nothing to warn of. Intake running 5 samples past the last batch leaves those 5 unplaced, counted once
// though the record starts before the damage.
TEST(JournalIntake, DamageLeavesUnplacedOnlyTheIntakePastTheBatches) {
    const std::vector<ToolSample> s = test::journal_stream();
    for (const auto& [end, unplaced] : {std::pair<std::size_t, std::uint64_t>{40, 0}, {45, 5}}) {
        SCOPED_TRACE("intake of 20.." + std::to_string(end - 1));
        const compute::Journal j = damaged_after_intake(s, end, "damaged_" + std::to_string(end) + ".tdj");
        ASSERT_EQ(j.damage.size(), 1u);
        EXPECT_FALSE(j.cut);
        EXPECT_EQ(j.damage[0].samples_lost, 10u);
        EXPECT_EQ(j.intake_samples, end - 20);
        EXPECT_EQ(j.tail_samples, 0u);
        EXPECT_EQ(j.tail_unplaced, unplaced);
    }
}

// The tail spans both stroke changes; the replay closes the strokes there, as the sculpt thread would have, and the
// dexels equal the whole stream applied at once.
TEST(JournalIntake, AReplayAppliesTheTailAsTheSculptThreadWould) {
    const std::vector<ToolSample> s = test::journal_stream();
    const std::string path = temp_path("replay.tdj");
    {
        compute::JournalWriter w(path, "session");
        w.append(part(s, 0, 100));
        w.intake(100, part(s, 100, 450));
    }
    const compute::Journal j = compute::read_journal(path);
    EXPECT_EQ(j.tail_samples, 350u);
    compute::TriDexel replayed = test::journal_box_model();
    const compute::JournalApplyStats st = compute::journal_apply(replayed, j.records);
    EXPECT_EQ(st.samples, 450u);
    EXPECT_EQ(st.tail_samples, 350u);
    EXPECT_EQ(st.strokes, 2u);  // subtract -> union and union -> paint closed; the paint stroke stays open
    EXPECT_DOUBLE_EQ(st.last_t_s, s.back().t_s);
    std::vector<compute::JournalRecord> one(1);
    one[0].samples = s;
    compute::TriDexel whole = test::journal_box_model();
    compute::journal_apply(whole, one);
    EXPECT_EQ(compute::model_digest(replayed), compute::model_digest(whole));
    fs::remove(path);
}

// The intake thread beside a sculpt thread that has not started: what the haptic loop pushed reaches the journal
// anyway; once the sculpt thread runs and journals its batches, the intake writes nothing twice, and the journal
// replays to the live model.
TEST(JournalIntake, TheThreadKeepsWhatTheSculptThreadHasNotApplied) {
    const std::vector<ToolSample> s = test::journal_stream();
    const std::string path = temp_path("thread.tdj");
    compute::TriDexel live = test::journal_box_model();
    compute::JournalStats stats;
    {
        compute::Contourer contourer(live);
        contourer.update(live);
        SpscRing<ToolSample> ring(512);
        TripleBuffer<ActiveSurface> surface;
        compute::JournalWriter journal(path, "session", std::chrono::milliseconds(5));
        compute::JournalIntake intake(journal);
        SculptThread t(live, contourer, ring, surface, Vec3(0.0));
        t.use_journal(journal);
        intake.start();
        std::uint64_t seq = 0;
        auto push = [&](std::size_t begin, std::size_t end) {  // as the haptic loop pushes
            for (std::size_t i = begin; i < end; ++i) {
                ASSERT_TRUE(ring.try_push(s[i]));
                ASSERT_TRUE(intake.ring().try_push(SequencedSample{seq++, s[i]}));
            }
        };
        push(0, 200);
        // No sculpt thread yet: the intake writes the 200 samples once they have waited JournalIntake::kHold.
        compute::Journal j;
        const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        do {
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
            j = compute::parse_journal(file_bytes(path), "thread.tdj");
        } while (j.tail_samples < 200 && std::chrono::steady_clock::now() < give_up);
        EXPECT_EQ(j.tail_samples, 200u);
        std::size_t n = 0;
        expect_prefix(j, s, n);
        EXPECT_EQ(n, 200u);
        t.start();
        for (std::size_t i = 200; i < s.size(); i += 25) {
            push(i, i + 25);
            // A snapshot at any moment: its batches and tail are a prefix of what was pushed, without a gap.
            expect_prefix(compute::parse_journal(file_bytes(path), "thread.tdj"), s, n);
            EXPECT_GE(n, 200u);
            std::this_thread::sleep_for(std::chrono::milliseconds(3));
        }
        t.stop();
        intake.stop();
        journal.close();
        stats = journal.stats();
    }
    EXPECT_EQ(stats.error, "");
    EXPECT_EQ(stats.samples, 450u);
    EXPECT_GE(stats.intake_samples, 200u);
    const compute::Journal j = compute::read_journal(path);
    EXPECT_EQ(j.tail_samples, 0u);  // everything it received, the sculpt thread applied and journalled
    std::size_t n = 0;
    expect_prefix(j, s, n);
    EXPECT_EQ(n, 450u);
    compute::TriDexel again = test::journal_box_model();
    compute::journal_apply(again, j.records);
    EXPECT_EQ(compute::model_digest(again), compute::model_digest(live));
    fs::remove(path);
}

}  // namespace
}  // namespace tridex::app
