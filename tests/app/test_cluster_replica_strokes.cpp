// A render rank's replica that draws strokes coarse (the cluster config's "stroke_contour": "coarse"): the tiles a
// stroke changes wait, hidden, while it is open, the coarse group levels over them stand in (finer where the frames
// want it), and once it closes those a view may see are contoured; the contour then equals, bit for bit, that of a
// replica that contoured every change at once, and the pictures meanwhile agree with it within a stated tolerance.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "app/session/cluster/cluster_replica.hpp"
#include "cluster_replica_helpers.hpp"
#include "gpu/context.hpp"
#include "renderer/image/image.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/output/offscreen_sink.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
using test::bunny_spec_json;
using test::expect_same_contour;
using test::small_wall;
using test::wall_frame;

// One frame's records: a batch of `per` subtract samples along the bunny's tail, the k-th of `of` such frames, the
// next record index `index` (counted on).
compute::JournalRecord stroke_step(int k, int of, int per, std::uint64_t& index) {
    compute::JournalRecord r;
    r.kind = compute::JournalKind::kBatch;
    r.index = index++;
    for (int i = 0; i < per; ++i) {
        const double u = static_cast<double>(per * k + i) / (per * of);
        ToolSample s;
        s.t_s = (per * k + i) * 1e-3;
        s.position = Vec3(-0.07 + 0.03 * u, 0.0, 0.05);
        s.tool.radius_m = 0.006;
        s.op = ToolOp::kSubtract;
        r.samples.push_back(s);
    }
    return r;
}

// A record of `kind` (a stroke's end, an undo) for the step `serial`.
compute::JournalRecord mark(compute::JournalKind kind, std::uint64_t serial, std::uint64_t& index) {
    compute::JournalRecord r;
    r.kind = kind;
    r.index = index++;
    r.serial = serial;
    return r;
}

// The bunny's wall drawn offscreen (320x240, mono) through validation.
class Wall {
public:
    Wall()
        : ctx_(make_context()),
          rend_(renderer::OffscreenStereoRenderer::create(ctx_, wall_.width_px, wall_.height_px)),
          sink_(ctx_,
                renderer::SinkOptions{renderer::StereoOutput::kMono, false, renderer::AnaglyphMethod::kDubois, 60.0}) {}

    // Draws `r` through frame `m`, and hands it the groups the frame wants finer and those it drew at a level, as a
    // render rank does.
    const renderer::FrameStats& draw(ClusterReplica& r, const FrameMessage& m) {
        (void)sink_.draw(rend_, r.view(m), ClusterReplica::camera(wall_, m));
        (void)sink_.present(rend_);
        const renderer::FrameStats& st = rend_.last_frame_stats();
        r.want_detail(st.groups_wanting_detail);
        r.frames_drew(st.groups_at_level);
        return st;
    }
    // `r`'s picture through `m`, written as `name`.
    renderer::Image picture(ClusterReplica& r, const FrameMessage& m, const std::string& name) {
        (void)draw(r, m);
        const fs::path dir = fs::path(::testing::TempDir()) / ("tridex_replica_strokes_" + name);
        fs::create_directories(dir);
        (void)sink_.finish(rend_, dir.string());
        return renderer::read_png((dir / "left.png").string());
    }
    std::size_t validation_messages() const { return ctx_.validation_messages(); }
    std::size_t pixels() const { return static_cast<std::size_t>(wall_.width_px) * wall_.height_px; }

private:
    static gpu::Context make_context() {
        gpu::ContextOptions o;
        o.validation = true;
        return gpu::Context::create(o);
    }
    ClusterViewport wall_ = small_wall();
    gpu::Context ctx_;
    renderer::OffscreenStereoRenderer rend_;
    renderer::OffscreenSink sink_;
};

// Pixels of `a` more than 24 levels off `b`.
std::size_t pixels_off(const renderer::Image& a, const renderer::Image& b) {
    const renderer::ImageComparison c = renderer::compare_images(a, b, 24);
    return c.pixels - c.within;
}

// A stroke of 40 frames (3 samples each) along the bunny's tail, drawn by two replicas that draw strokes coarse:
// - `unseen`, whose frames ask for nothing (a view where the coarse levels are within the pixel bound), contours no
//   tile while it is open: its changed tiles wait, hidden, and the coarse levels stand in;
// - `seen`, drawn frame by frame with the bunny at four times its size on the wall and each frame's wanted detail
//   handed back (as a render rank does), contours the tiles under the groups its frames want finer, in fewer tile
//   contours than a replica that contoured every frame's change; its picture in the stroke's last frame is as close
//   to that replica's (without levels) as one whose levels are built from the whole contour (at most 1.5 times its
//   pixels more than 24 levels off, plus 20);
// and once the stroke closes, a view of everything contours what waits, and both contours equal, bit for bit, that of
// the replica that contoured every change at once.
TEST(ClusterReplicaStrokes, AStrokeDrawnCoarseWaitsHiddenWhereNoFrameWantsItAndEndsInTheWholeContour) {
    const std::string json = bunny_spec_json(128);
    const LodChoice levels = lod_choice("coarse");
    ClusterReplica unseen(json, levels, nullptr, {.stroke_coarse = true}),
        seen(json, levels, nullptr, {.stroke_coarse = true}), lod(json, levels), full(json);
    ASSERT_TRUE(unseen.strokes_coarse());
    EXPECT_FALSE(lod.strokes_coarse());
    EXPECT_FALSE(ClusterReplica(json, {}, nullptr, {.stroke_coarse = true}).strokes_coarse()) << "no coarse groups";
    const std::uint64_t unseen_first = unseen.tiles_contoured(), seen_first = seen.tiles_contoured(),
                        full_first = full.tiles_contoured();
    Wall wall;
    const FrameMessage m = wall_frame(4.0);
    constexpr int kFrames = 40;
    std::uint64_t index = 0;
    for (int k = 0; k < kFrames; ++k) {
        FrameMessage step;
        step.records.push_back(stroke_step(k, kFrames, 3, index));
        for (ClusterReplica* r : {&unseen, &seen, &lod, &full}) {
            r->apply(step);
            r->contour();
        }
        (void)wall.draw(seen, m);
    }
    ASSERT_EQ(unseen.digest(), full.digest());
    const std::uint64_t by_unseen = unseen.tiles_contoured() - unseen_first,
                        by_seen = seen.tiles_contoured() - seen_first, by_full = full.tiles_contoured() - full_first;
    const std::size_t waiting = unseen.stroke_tiles_waiting();
    EXPECT_EQ(by_unseen, 0u);
    EXPECT_GT(waiting, 0u);
    EXPECT_GT(by_seen, 0u) << "no frame wanted the stroke finer";
    EXPECT_LT(by_seen, by_full);
    // Levels from the whole contour: until the worker's and the coarse levels are in (at most 60 s).
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    do {
        lod.contour();
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    } while ((lod.lod_pending() > 0 || lod.coarse_levels_waiting() > 0) && std::chrono::steady_clock::now() < until);
    const renderer::Image whole = wall.picture(full, m, "whole");
    const std::size_t seen_off = pixels_off(wall.picture(seen, m, "open"), whole);
    const std::size_t lod_off = pixels_off(wall.picture(lod, m, "levels"), whole);

    FrameMessage close;
    close.records.push_back(mark(compute::JournalKind::kStrokeEnd, 1, index));
    for (ClusterReplica* r : {&unseen, &seen, &full}) r->apply(close);
    full.contour();
    int after = 0;  // frames after the close (whose own frame defers what it changes, as the stroke's)
    for (; after < 100 && unseen.stroke_tiles_waiting() + seen.stroke_tiles_waiting() > 0; ++after) {
        unseen.contour();
        seen.contour();
    }
    std::printf(
        "[replica strokes] while the stroke was open: tile contours %llu unseen, %llu seen, %llu contouring every "
        "change; %zu tiles waited unseen (%llu deferrals); seen %zu pixels over 24 levels off (levels from the whole "
        "contour %zu); %d frames after it: %llu and %llu tile contours in all\n",
        static_cast<unsigned long long>(by_unseen), static_cast<unsigned long long>(by_seen),
        static_cast<unsigned long long>(by_full), waiting,
        static_cast<unsigned long long>(unseen.stroke_tiles_deferred()), seen_off, lod_off, after,
        static_cast<unsigned long long>(unseen.tiles_contoured() - unseen_first),
        static_cast<unsigned long long>(seen.tiles_contoured() - seen_first));
    EXPECT_LE(seen_off, lod_off * 3 / 2 + 20);
    for (const ClusterReplica* r : {&unseen, &seen}) {
        EXPECT_EQ(r->stroke_tiles_waiting(), 0u);
        expect_same_contour(*r, full);
    }
    EXPECT_EQ(wall.validation_messages(), 0u);
}

// Up close (the bunny at 24 times its size), with the replicas' levels settled first, a stroke's frames want detail
// where its coarse levels are over the pixel bound: the deferred tiles under those groups are contoured while the
// stroke is open, and its last frame's picture is closer to the whole contour's than that of a replica that contours
// a stroke's tiles as they change (its finer levels within the stroke's reach wait for the stroke to settle, and
// coarser ones stand in). With the stroke still open and the hand at rest, frames until five in a row want no detail
// and no coarse level waits (at most 60 s): the picture is then within 1 % of the pixels (more than 24 levels off)
// of the whole contour's.
TEST(ClusterReplicaStrokes, UpCloseTheFramesGetAStrokesTilesWhereTheyWantDetail) {
    const std::string json = bunny_spec_json(128);
    const LodChoice levels = lod_choice("coarse");
    ClusterReplica coarse(json, levels, nullptr, {.stroke_coarse = true}), plain(json, levels), full(json);
    Wall wall;
    const FrameMessage m = wall_frame(24.0);
    // Frames until five in a row want no detail and no level waits in `r` (at most 60 s); how many, or -1 when the
    // frames never calmed down.
    const auto settle = [&](ClusterReplica& r) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        int frames = 0, quiet = 0;
        for (; quiet < 5 && std::chrono::steady_clock::now() < until; ++frames) {
            r.contour();
            const renderer::FrameStats& st = wall.draw(r, m);
            const bool calm =
                st.groups_wanting_detail.empty() && r.coarse_levels_waiting() == 0 && r.lod_pending() == 0;
            quiet = calm ? quiet + 1 : 0;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return quiet == 5 ? frames : -1;
    };
    ASSERT_GE(settle(coarse), 0) << "the frames never calmed down before the stroke";
    ASSERT_GE(settle(plain), 0) << "the frames never calmed down before the stroke";
    const std::uint64_t first = coarse.tiles_contoured();
    constexpr int kFrames = 40;
    std::uint64_t index = 0;
    std::size_t wanting = 0;
    for (int k = 0; k < kFrames; ++k) {
        FrameMessage step;
        step.records.push_back(stroke_step(k, kFrames, 3, index));
        for (ClusterReplica* r : {&coarse, &plain, &full}) {
            r->apply(step);
            r->contour();
        }
        wanting += wall.draw(coarse, m).groups_wanting_detail.size();
        (void)wall.draw(plain, m);
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    const renderer::Image whole = wall.picture(full, m, "near_whole");
    const std::uint64_t contoured = coarse.tiles_contoured() - first;
    const std::size_t waiting = coarse.stroke_tiles_waiting();
    const std::size_t stroke_off = pixels_off(wall.picture(coarse, m, "near_stroke"), whole);
    const std::size_t plain_off = pixels_off(wall.picture(plain, m, "near_stroke_full"), whole);
    const int frames = settle(coarse);
    const std::size_t rest_off = pixels_off(wall.picture(coarse, m, "near_rest"), whole);
    std::printf(
        "[replica strokes] up close: %zu groups wanted detail over the stroke; %llu tiles contoured during it, "
        "%zu waited at its last frame; pixels over 24 levels off then %zu (contouring the stroke's tiles as "
        "they change: %zu), %zu of %zu after %d frames at rest\n",
        wanting, static_cast<unsigned long long>(contoured), waiting, stroke_off, plain_off, rest_off, wall.pixels(),
        frames);
    EXPECT_GT(wanting, 0u);
    EXPECT_GT(contoured, 0u) << "no tile under a group the frames wanted finer was contoured";
    EXPECT_LT(stroke_off, plain_off);
    EXPECT_GE(frames, 0) << "the frames never stopped wanting detail";
    EXPECT_LE(rest_off * 100, wall.pixels());
    EXPECT_EQ(wall.validation_messages(), 0u);
}

// Two grooves as one stroke, closed, and a view of the left end only: the left groove's deferred tiles are contoured,
// the right one's wait (frame after frame); an undo then takes the deferred tiles it reaches along (no tile borrows a
// vertex from an old contour), a view of everything contours the rest, and the contour equals that of a replica that
// contoured every change at once, bit for bit.
TEST(ClusterReplicaStrokes, AStrokesTilesNoViewSeesWaitAfterItClosesAndAnUndoTakesThemAlong) {
    const std::string json = bunny_spec_json(256);
    ClusterReplica coarse(json, lod_choice("coarse"), nullptr, {.stroke_coarse = true}), full(json);
    std::uint64_t index = 0;
    FrameMessage stroke;
    for (const double x0 : {-0.09, 0.04}) {  // the left end (x -0.09 .. -0.05), then the right (0.04 .. 0.08)
        compute::JournalRecord r;
        r.kind = compute::JournalKind::kBatch;
        r.index = index++;
        for (int i = 0; i <= 20; ++i) {
            ToolSample s;
            s.t_s = static_cast<double>(r.samples.size() + (x0 > 0.0 ? 100 : 0)) * 1e-3;
            s.position = Vec3(x0 + 0.04 * i / 20.0, 0.0, 0.05);
            s.tool.radius_m = 0.008;
            s.op = ToolOp::kSubtract;
            r.samples.push_back(s);
        }
        stroke.records.push_back(r);
    }
    for (ClusterReplica* r : {&coarse, &full}) {
        r->apply(stroke);
        r->contour();
    }
    const std::size_t deferred = coarse.stroke_tiles_waiting();
    ASSERT_GT(deferred, 0u);
    FrameMessage close;
    close.records.push_back(mark(compute::JournalKind::kStrokeEnd, 1, index));
    renderer::Frustum left;  // everything with x <= -0.03 m
    for (glm::dvec4& p : left.planes) p = glm::dvec4(0.0, 0.0, 0.0, 1.0);
    left.planes[0] = glm::dvec4(-1.0, 0.0, 0.0, -0.03);
    const renderer::Frustum frusta[] = {left};
    for (ClusterReplica* r : {&coarse, &full}) r->apply(close);
    full.contour();
    for (int i = 0; i < 50; ++i) coarse.contour(frusta);
    const std::size_t right = coarse.stroke_tiles_waiting();
    for (int i = 0; i < 5; ++i) {
        coarse.contour(frusta);
        EXPECT_EQ(coarse.stroke_tiles_waiting(), right) << "frame " << i;
    }
    std::printf("[replica strokes] two grooves: %zu tiles deferred; a view of the left end left %zu waiting\n",
                deferred, right);
    EXPECT_GT(right, 0u) << "the right groove's tiles were contoured though no view sees them";
    EXPECT_LT(right, deferred) << "the left groove's tiles were not contoured";

    FrameMessage undo;
    ++index;  // after a gap in the indices the replay matches the undo by its serial alone, not the rays it writes back
    undo.records.push_back(mark(compute::JournalKind::kUndo, 1, index));
    for (ClusterReplica* r : {&coarse, &full}) {
        r->apply(undo);
        r->contour();
    }
    ASSERT_EQ(coarse.digest(), full.digest());
    EXPECT_EQ(coarse.stroke_tiles_waiting(), 0u) << "the undo reaches every deferred tile";
    coarse.contour();
    expect_same_contour(coarse, full);
}

// A groove across the bunny along x from x0 to x1 at height z (m), as one batch record.
compute::JournalRecord groove(double x0, double x1, double z, std::uint64_t& index) {
    compute::JournalRecord r;
    r.kind = compute::JournalKind::kBatch;
    r.index = index++;
    for (int i = 0; i <= 20; ++i) {
        ToolSample s;
        s.t_s = static_cast<double>(index * 100 + i) * 1e-3;
        s.position = Vec3(x0 + (x1 - x0) * i / 20.0, 0.0, z);
        s.tool.radius_m = 0.006;
        s.op = ToolOp::kSubtract;
        r.samples.push_back(s);
    }
    return r;
}

// With a view of the left end in every frame (as a render rank always has): a stroke across the view's edge, then a
// second one beside its unseen part, then an undo of the second. The undo's change waits for a view next to the
// first stroke's unseen waiting tiles, and no frame throws (a tile drawn borrowing a vertex its neighbour's old contour
// lacks); a view of everything then gives the contour of a replica that contoured every change at once, bit for bit.
TEST(ClusterReplicaStrokes, AnUndoNoViewSeesBesideAStrokesWaitingTilesWaitsWithThem) {
    const std::string json = bunny_spec_json(256);
    ClusterReplica coarse(json, lod_choice("coarse"), nullptr, {.stroke_coarse = true}), full(json);
    renderer::Frustum left;  // everything with x <= -0.03 m
    for (glm::dvec4& p : left.planes) p = glm::dvec4(0.0, 0.0, 0.0, 1.0);
    left.planes[0] = glm::dvec4(-1.0, 0.0, 0.0, -0.03);
    const renderer::Frustum frusta[] = {left};
    std::uint64_t index = 0;
    const auto frame = [&](const compute::JournalRecord& r, int frames) {
        FrameMessage m;
        m.records.push_back(r);
        for (ClusterReplica* c : {&coarse, &full}) c->apply(m);
        full.contour();
        ASSERT_NO_THROW(coarse.contour(frusta));
        for (int i = 1; i < frames; ++i) ASSERT_NO_THROW(coarse.contour(frusta));
    };
    frame(groove(-0.06, 0.0, 0.05, index), 1);  // across the view's edge
    frame(mark(compute::JournalKind::kStrokeEnd, 1, index), 20);
    const std::size_t unseen = coarse.stroke_tiles_waiting();
    frame(groove(-0.01, 0.03, 0.045, index), 1);  // beside the first one's unseen part
    frame(mark(compute::JournalKind::kStrokeEnd, 2, index), 20);
    ++index;  // after a gap in the indices the replay matches the undo by its serial alone
    frame(mark(compute::JournalKind::kUndo, 2, index), 5);
    ASSERT_EQ(coarse.digest(), full.digest());
    std::printf(
        "[replica strokes] a stroke across the view's edge left %zu tiles unseen; after a second beside them and "
        "its undo, %zu deferred and %zu changed tiles wait\n",
        unseen, coarse.stroke_tiles_waiting(), coarse.tiles_deferred());
    EXPECT_GT(unseen, 0u);
    coarse.contour();
    EXPECT_EQ(coarse.stroke_tiles_waiting(), 0u);
    expect_same_contour(coarse, full);
}

}  // namespace
}  // namespace tridex::app
