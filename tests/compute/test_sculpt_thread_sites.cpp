// Several sites in one sculpt thread (a shared session): each site's sweeps join only its own samples, strokes close
// where another site's tool cuts, personal undo takes back only the asker's newest stroke and is refused (naming who
// stands in the way) when another site's stroke is newer or interrupted it, and the journal of such a session replays
// to the same dexels bit for bit.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

#include "compute/journal/journal_format.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/journal/journal_writer.hpp"
#include "compute/journal/stream_buffer.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/error.hpp"
#include "journal_stream.hpp"
#include "sculpt_passes.hpp"
#include "site_grooves.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

// box_model, groove and slice: site_grooves.hpp.

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

TEST(SculptSites, AToolRestingInMaterialNeverStandsInTheWayOfAnotherSitesUndo) {
    const std::string path = temp_path("tridex_sites_rest_");
    compute::TriDexel live = box_model();
    const std::uint64_t before = compute::model_digest(live);
    std::vector<ToolSample> rest = groove(1, -0.02, 0.0, 0.0, 400, 3.0);  // site 1 holds its tool still, cutting
    rest.pop_back();                                                       // and never lifts it
    {
        Rig rig(live, path);
        rig.intake.push_samples(std::vector<ToolSample>(rest.begin(), rest.begin() + 200));
        rig.settle();
        const std::uint64_t rested = compute::model_digest(live);  // its first sweep cut a ball's worth once
        const std::vector<ToolSample> a = groove(0, 0.02, -0.03, 0.03, 80, 0.0);
        for (std::size_t i = 0; i < a.size(); i += 10) {  // the host's stroke, interleaved with the resting tool
            rig.own(slice(a, i, std::min(a.size(), i + 10)));
            rig.settle();
            rig.intake.push_samples(slice(rest, 200 + i, 210 + i));
            rig.settle();
        }
        ASSERT_TRUE(rig.thread.request(SculptRequest::kUndo));  // the host's whole groove, every part of it
        rig.settle();
        ASSERT_TRUE(rig.thread.request(SculptRequest::kUndo));  // then: site 1's resting cut is site 1's to undo
        rig.settle();
        EXPECT_EQ(compute::model_digest(live), rested);
        rig.thread.stop();
        ASSERT_EQ(rig.thread.stats().refusals.size(), 1u);
        EXPECT_EQ(rig.thread.stats().refusals[0].by_site, 1);
        EXPECT_GE(rig.thread.stats().history.undos, 1u);
    }
    EXPECT_NE(before, compute::model_digest(live));
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
    EXPECT_EQ(heard[0].by_site, 0);  // C was open: its first part is newer than anything of site 1's
    EXPECT_EQ(heard[1].site, 0);
    EXPECT_EQ(heard[1].by_site, 1);  // B interrupted C
    const compute::Journal j = compute::read_journal(path);
    compute::TriDexel again = box_model();
    compute::journal_apply(again, j.records);
    EXPECT_EQ(compute::model_digest(again), compute::model_digest(live));
    fs::remove(path);
}

// Moves the host's stream into a follower's intake (what a network thread does).
void relay(compute::ToolStreamBuffer& stream, SiteIntake& follower) {
    for (const compute::JournalRecord& r : stream.take().records) follower.push_host_record(r);
}

TEST(SculptSites, AJoinerFollowsTheHostsStreamWhileItsOwnToolCarvesThroughTheHost) {
    compute::TriDexel host_model = box_model();
    compute::TriDexel join_model = box_model();
    compute::ToolStreamBuffer stream;
    SiteIntake host_in, join_in;
    std::vector<SculptRequest> asked;
    std::mutex asked_mutex;
    compute::Contourer hc(host_model), jc(join_model);
    hc.update(host_model);
    jc.update(join_model);
    SpscRing<ToolSample> host_ring(4096), join_ring(4096);
    TripleBuffer<ActiveSurface> hs, js;
    SculptThread host(host_model, hc, host_ring, hs, Vec3(0.0));
    SculptThread join(join_model, jc, join_ring, js, Vec3(0.0));
    host.use_stream(stream);
    host.use_site_intake(host_in);
    EXPECT_THROW(join.follow_host(join_in, 0, {}), Error);
    join.follow_host(join_in, 3,
                     {[&](std::span<const ToolSample> s) { host_in.push_samples(s); },
                      [&](SculptRequest r) {
                          std::lock_guard lock(asked_mutex);
                          asked.push_back(r);
                          host_in.push_request(3, r);
                      },
                      {}});
    host.start();
    join.start();
    const auto settle = [&] {
        for (int k = 0; k < 40; ++k) {  // a few round trips of the "network"
            relay(stream, join_in);
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    };
    std::vector<ToolSample> mine = groove(0, -0.02, 0.03, -0.03, 90, 2.0);  // the joiner's haptic loop: site 0 there
    for (const ToolSample& x : groove(0, 0.02, -0.03, 0.03, 90, 0.0)) host_ring.try_push(x);
    settle();
    for (const ToolSample& x : mine) join_ring.try_push(x);  // after the host's: the joiner's stroke is the newest
    settle();
    ASSERT_TRUE(join.request(SculptRequest::kUndo));  // the joiner's own groove, taken back through the host
    settle();
    const std::uint64_t after_undo = compute::model_digest(host_model);
    ASSERT_TRUE(join.request(SculptRequest::kRedo));
    settle();
    host.stop();
    relay(stream, join_in);
    settle();
    join.stop();
    EXPECT_EQ(join.stats().forwarded, mine.size());
    EXPECT_EQ(host.stats().site_samples, mine.size());
    EXPECT_EQ(join.stats().site_samples, 2 * mine.size());  // every site's samples came back from the host
    EXPECT_EQ(host.stats().history.undos, 1u);
    EXPECT_EQ(host.stats().history.redos, 1u);
    EXPECT_EQ(join.stats().undo_ms.size(), 2u);  // the host's undo and redo, followed
    EXPECT_TRUE(join.stats().refusals.empty());
    EXPECT_EQ(asked.size(), 2u);
    EXPECT_EQ(compute::model_digest(join_model), compute::model_digest(host_model));

    // After the undo only the host's own groove was left.
    compute::TriDexel only_host = box_model();
    compute::JournalRecord r;
    r.kind = compute::JournalKind::kBatch;
    r.samples = groove(0, 0.02, -0.03, 0.03, 90, 0.0);
    compute::journal_apply(only_host, std::span<const compute::JournalRecord>(&r, 1));
    EXPECT_EQ(after_undo, compute::model_digest(only_host));
}

// A joiner whose strokes end on release (the mouse) holds an undo asked while its tool still cuts and sends it to the
// host only after its samples up to the release, so the host takes back the whole drag; the host's echo of one of its
// own samples that does not cut is not taken for the release.
TEST(SculptSites, AJoinersUndoAskedMidDragReachesTheHostAfterItsRelease) {
    compute::TriDexel model = box_model();
    compute::Contourer contourer(model);
    contourer.update(model);
    SpscRing<ToolSample> ring(4096);
    TripleBuffer<ActiveSurface> surface;
    SiteIntake in;
    std::mutex log_mutex;
    std::vector<std::size_t> sent_before_request;  // per request: the samples the host had been sent before it
    std::size_t sent = 0;
    SculptThread join(model, contourer, ring, surface, Vec3(0.0));
    join.strokes_end_on_release(true);
    join.follow_host(in, 2,
                     {[&](std::span<const ToolSample> s) {
                          std::lock_guard lock(log_mutex);
                          sent += s.size();
                      },
                      [&](SculptRequest) {
                          std::lock_guard lock(log_mutex);
                          sent_before_request.push_back(sent);
                      },
                      {}});
    join.start();
    const auto settle = [&] { test::wait_drained(ring, join); };
    std::vector<ToolSample> drag = groove(0, -0.02, 0.03, -0.03, 90, 0.0);
    ToolSample release = drag.back();  // the groove's last sample lifts the tool: held back until after the request
    drag.pop_back();
    for (const ToolSample& x : drag) ASSERT_TRUE(ring.try_push(x));
    settle();
    ASSERT_TRUE(join.request(SculptRequest::kUndo));  // the button still held
    settle();
    // The host's echo of one of this joiner's own earlier samples, not cutting (a hover before the drag): it is not
    // the release.
    ToolSample echo = release;
    echo.site = 2;
    echo.t_s = -1.0;
    in.push_host_samples(std::span<const ToolSample>(&echo, 1));
    for (int k = 0; k < 100 && in.pending() > 0; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    settle();
    {
        std::lock_guard lock(log_mutex);
        EXPECT_TRUE(sent_before_request.empty()) << "sent while the tool still cut";
    }
    ASSERT_TRUE(ring.try_push(release));
    settle();
    join.stop();
    ASSERT_EQ(sent_before_request.size(), 1u);
    EXPECT_EQ(sent_before_request[0], drag.size() + 1) << "the request follows the release sample";
    EXPECT_EQ(join.stats().held_requests, 1u);
}

// A follower on the box that sends nothing anywhere and keeps what its outlet heard of a mismatch.
struct LoneFollower {
    explicit LoneFollower(std::uint8_t site) : model(box_model()), contourer(model) {
        contourer.update(model);
        thread = std::make_unique<SculptThread>(model, contourer, ring, surface, Vec3(0.0));
        thread->follow_host(in, site, {[](std::span<const ToolSample>) {}, [](SculptRequest) {},
                                       [this](const std::string& what) { heard = what; }});
        thread->start();
    }
    compute::TriDexel model;
    compute::Contourer contourer;
    SpscRing<ToolSample> ring{16};
    TripleBuffer<ActiveSurface> surface;
    SiteIntake in;
    std::string heard;
    std::unique_ptr<SculptThread> thread;
};

TEST(SculptSites, AFollowerThatHoldsAnotherModelFailsAtTheHostsMark) {
    LoneFollower f(1);
    f.in.push_host_samples(groove(2, 0.0, -0.03, 0.03, 30, 0.0));
    f.in.push_host_mark(compute::kJournalStrokeEnd, 7, 0);  // the host's stroke 7: this replica's is 1
    EXPECT_THROW(f.in.push_host_mark(99, 1, 0), Error);
    try {
        f.thread->stop();
        ADD_FAILURE() << "the follower did not fail";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("closed stroke 7 where this replica closed 1"), std::string::npos) << e.what();
    }
}

TEST(SculptSites, AFollowerChecksItsModelAtTheHostsDigestAndStopsWhenItDiffers) {
    LoneFollower f(2);
    const std::uint64_t start = compute::model_digest(box_model());
    f.in.push_host_check(start);  // agrees
    f.in.push_host_samples(groove(1, 0.0, -0.03, 0.03, 30, 0.0));
    f.in.push_host_check(start);  // the host's model did not change: this one did
    EXPECT_THROW(f.thread->stop(), Error);
    EXPECT_EQ(f.thread->stats().digest_checks, 2u);
    EXPECT_NE(f.heard.find("differs from the host's"), std::string::npos) << f.heard;
}

}  // namespace
}  // namespace tridex::app
