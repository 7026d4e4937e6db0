// Several sites in one sculpt thread (a shared session): each site's sweeps join only its own samples, strokes close
// where another site's tool cuts, personal undo takes back only the asker's newest stroke and is refused (naming who
// stands in the way) when another site's stroke is newer or interrupted it, and the journal of such a session replays
// to the same dexels bit for bit.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "compute/journal/journal_format.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/journal/journal_writer.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

compute::TriDexel box_model() {
    compute::TriDexel m =
        compute::TriDexel::empty(compute::Lattice::around(Aabb{Vec3(-0.05), Vec3(0.05)}, 40), std::size_t(1) << 30);
    compute::scan_convert(box_mesh(Aabb{Vec3(-0.0487), Vec3(0.0487)}), m);
    return m;
}

// A groove of `n` samples along x on the top face at height y_m, by `site`, starting at device time t0_s; the last
// sample lifts the tool (op none), which ends the stroke.
std::vector<ToolSample> groove(std::uint8_t site, double y_m, double x0_m, double x1_m, int n, double t0_s) {
    std::vector<ToolSample> s(static_cast<std::size_t>(n) + 1);
    for (int i = 0; i <= n; ++i) {
        ToolSample& x = s[static_cast<std::size_t>(i)];
        x.site = site;
        x.t_s = t0_s + i * 1e-3;
        x.position = Vec3(x0_m + (x1_m - x0_m) * std::min(i, n - 1) / (n - 1), y_m, 0.046);
        x.tool.radius_m = 0.005;
        x.op = i < n ? ToolOp::kSubtract : ToolOp::kNone;
    }
    return s;
}

std::vector<ToolSample> slice(const std::vector<ToolSample>& s, std::size_t a, std::size_t b) {
    return {s.begin() + static_cast<std::ptrdiff_t>(a), s.begin() + static_cast<std::ptrdiff_t>(b)};
}

// A sculpt thread with its own tool's ring, another sites' intake and a journal.
struct Rig {
    explicit Rig(compute::TriDexel& model, const std::string& journal_path)
        : contourer(model), contoured((contourer.update(model), true)),
          journal(journal_path, "session", std::chrono::milliseconds(5)),
          thread(model, contourer, ring, surface, Vec3(0.0)) {
        thread.use_journal(journal);
        thread.use_site_intake(intake);
        thread.start();
    }
    compute::Contourer contourer;
    bool contoured;
    SpscRing<ToolSample> ring{4096};
    SiteIntake intake;
    TripleBuffer<ActiveSurface> surface;
    compute::JournalWriter journal;
    SculptThread thread;

    // Every sample and request queued so far has taken effect (the ring and the intake are empty and two more passes
    // finished). Fails the test after a minute instead of hanging.
    void settle() {
        const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        while ((ring.size() > 0 || intake.pending() > 0) && std::chrono::steady_clock::now() < limit)
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        const std::uint64_t k = thread.passes();
        while (thread.passes() < k + 2 && std::chrono::steady_clock::now() < limit)
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        if (std::chrono::steady_clock::now() >= limit) ADD_FAILURE() << "the sculpt thread did not settle within 60 s";
    }
    void own(const std::vector<ToolSample>& s) {
        for (const ToolSample& x : s)
            while (!ring.try_push(x)) std::this_thread::yield();
    }
};

std::string temp_path(const char* name) {
    return (fs::temp_directory_path() / (std::string(name) + std::to_string(::getpid()) + ".tdj")).string();
}

TEST(SculptSites, ASampleKeepsItsSiteInTheJournalAndABadSiteIsRefused) {
    ToolSample s, back;
    s.site = 5;
    unsigned char b[compute::kJournalSampleBytes];
    compute::encode_sample(s, b);
    ASSERT_TRUE(compute::decode_sample(b, back));
    EXPECT_EQ(back.site, 5);
    b[118] = kMaxSites;
    EXPECT_FALSE(compute::decode_sample(b, back));
    b[118] = 1;
    b[119] = 1;  // reserved
    EXPECT_FALSE(compute::decode_sample(b, back));
    SiteIntake intake;
    EXPECT_THROW(intake.push_samples(groove(0, 0.0, 0.0, 0.01, 3, 0.0)), Error);  // site 0 is the host's own ring
    EXPECT_THROW(intake.push_request(kMaxSites, SculptRequest::kUndo), Error);
    EXPECT_THROW(intake.push_request(2, SculptRequest::kSave), Error);
    EXPECT_EQ(intake.pending(), 0u);
}

TEST(SculptSites, TwoSitesCarvingAtOnceCutOnlyTheirOwnGroovesAndReplayBitForBit) {
    const std::string path = temp_path("tridex_sites_");
    compute::TriDexel live = box_model();
    const std::vector<ToolSample> a = groove(0, 0.02, -0.03, 0.03, 120, 0.0);
    const std::vector<ToolSample> b = groove(1, -0.02, 0.03, -0.03, 120, 7.0);  // another clock
    std::uint64_t strokes = 0;
    {
        Rig rig(live, path);
        // Interleaved in slices, as two people carving at once reach the host.
        for (std::size_t i = 0; i < a.size(); i += 20) {
            rig.own(slice(a, i, std::min(a.size(), i + 20)));
            rig.settle();
            rig.intake.push_samples(slice(b, i, std::min(b.size(), i + 20)));
            rig.settle();
        }
        rig.thread.stop();
        EXPECT_EQ(rig.thread.stats().site_samples, b.size());
        EXPECT_EQ(rig.thread.stats().booleans, 2u * 119u);  // each site's sweeps join its own samples only
        strokes = rig.thread.stats().history.strokes;
    }
    EXPECT_GE(strokes, 6u);  // each slice of each site is a stroke of its own: the other's cut closed it

    // The same grooves one after the other, each from its own first sample: Booleans of disjoint rays commute.
    compute::TriDexel apart = box_model();
    for (const std::vector<ToolSample>* g : {&a, &b}) {
        compute::JournalRecord r;
        r.kind = compute::JournalKind::kBatch;
        r.samples = *g;
        compute::journal_apply(apart, std::span<const compute::JournalRecord>(&r, 1));
    }
    EXPECT_EQ(compute::model_digest(live), compute::model_digest(apart));

    // Joining the two tools into one stream (every sample site 0) carves between the grooves: the sites matter.
    const compute::Journal j = compute::read_journal(path);
    std::vector<compute::JournalRecord> one_tool = j.records;
    for (compute::JournalRecord& r : one_tool)
        for (ToolSample& s : r.samples) s.site = 0;
    compute::TriDexel joined = box_model();
    try {
        compute::journal_apply(joined, one_tool);
    } catch (const Error&) {
        // the marks no longer match the strokes of one tool: the replay may refuse; either way it is not the model
    }
    EXPECT_NE(compute::model_digest(joined), compute::model_digest(live));

    compute::TriDexel again = box_model();
    const compute::JournalApplyStats st = compute::journal_apply(again, j.records);
    EXPECT_EQ(st.samples, a.size() + b.size());
    EXPECT_EQ(compute::model_digest(again), compute::model_digest(live));
    fs::remove(path);
}

TEST(SculptSites, UndoIsPersonalAndRefusedNamingWhoCarvedSince) {
    const std::string path = temp_path("tridex_sites_undo_");
    compute::TriDexel live = box_model();
    const std::uint64_t before = compute::model_digest(live);
    std::vector<SculptRefusal> heard;
    std::uint64_t after_a = 0;
    {
        Rig rig(live, path);
        rig.own(groove(0, 0.02, -0.03, 0.03, 60, 0.0));  // A, the host's
        rig.settle();
        rig.intake.push_samples(groove(1, -0.02, 0.03, -0.03, 60, 5.0));  // B, site 1's
        rig.settle();
        ASSERT_TRUE(rig.thread.request(SculptRequest::kUndo));  // the host's undo: B is newer
        rig.settle();
        rig.intake.push_request(1, SculptRequest::kUndo);  // site 1 takes B back
        rig.settle();
        after_a = compute::model_digest(live);
        rig.intake.push_request(1, SculptRequest::kUndo);  // site 1's next would be A: the host's
        rig.intake.push_request(1, SculptRequest::kRedo);  // site 1 redoes B
        rig.settle();
        ASSERT_TRUE(rig.thread.request(SculptRequest::kRedo));  // the next redo is nobody's: nothing happens
        ASSERT_TRUE(rig.thread.request(SculptRequest::kUndo));  // B is on top again: refused
        rig.settle();
        rig.thread.stop();
        heard = rig.thread.stats().refusals;
        EXPECT_EQ(rig.thread.stats().history.undos, 1u);
        EXPECT_EQ(rig.thread.stats().history.redos, 1u);
    }
    ASSERT_EQ(heard.size(), 3u);
    EXPECT_EQ(heard[0].site, 0);
    EXPECT_EQ(heard[0].by_site, 1);
    EXPECT_EQ(heard[0].request, SculptRequest::kUndo);
    EXPECT_EQ(heard[1].site, 1);
    EXPECT_EQ(heard[1].by_site, 0);
    EXPECT_EQ(heard[2].site, 0);
    EXPECT_EQ(heard[2].by_site, 1);
    EXPECT_NE(after_a, before);  // A stayed while B was undone

    compute::TriDexel only_a = box_model();
    {
        compute::JournalRecord r;
        r.kind = compute::JournalKind::kBatch;
        r.samples = groove(0, 0.02, -0.03, 0.03, 60, 0.0);
        compute::journal_apply(only_a, std::span<const compute::JournalRecord>(&r, 1));
    }
    EXPECT_EQ(after_a, compute::model_digest(only_a));  // undoing B left exactly A

    const compute::Journal j = compute::read_journal(path);
    compute::TriDexel again = box_model();
    const compute::JournalApplyStats st = compute::journal_apply(again, j.records);
    EXPECT_EQ(st.undos, 1u);
    EXPECT_EQ(st.redos, 1u);
    EXPECT_EQ(compute::model_digest(again), compute::model_digest(live));
    fs::remove(path);
}

TEST(SculptSites, AGestureAnotherSiteInterruptedCannotBeUndoneAndAnOpenStrokeIsNotClosedByOthers) {
    const std::string path = temp_path("tridex_sites_gesture_");
    compute::TriDexel live = box_model();
    const std::vector<ToolSample> c = groove(0, 0.02, -0.03, 0.03, 80, 0.0);
    std::vector<SculptRefusal> heard;
    {
        Rig rig(live, path);
        rig.own(slice(c, 0, 40));  // C begins (still open: no lift yet)
        rig.settle();
        rig.intake.push_request(1, SculptRequest::kUndo);  // site 1 may not close or take back C
        rig.settle();
        rig.intake.push_samples(groove(1, -0.02, 0.03, -0.03, 30, 5.0));  // B interrupts C
        rig.settle();
        rig.own(slice(c, 40, c.size()));  // C goes on, then lifts
        rig.settle();
        ASSERT_TRUE(rig.thread.request(SculptRequest::kUndo));  // C's second part: B came during the gesture
        rig.settle();
        rig.thread.stop();
        heard = rig.thread.stats().refusals;
        EXPECT_EQ(rig.thread.stats().history.undos, 0u);
    }
    ASSERT_EQ(heard.size(), 2u);
    EXPECT_EQ(heard[0].site, 1);
    EXPECT_EQ(heard[0].by_site, 0);  // C was open
    EXPECT_EQ(heard[0].serial, 0u);
    EXPECT_EQ(heard[1].site, 0);
    EXPECT_EQ(heard[1].by_site, 1);  // B interrupted C
    const compute::Journal j = compute::read_journal(path);
    compute::TriDexel again = box_model();
    compute::journal_apply(again, j.records);
    EXPECT_EQ(compute::model_digest(again), compute::model_digest(live));
    fs::remove(path);
}

}  // namespace
}  // namespace tridex::app
