// A render rank's replica contours only the changed tiles its viewports can see (with the tiles next to them, and
// the rest of their group of changed tiles); the rest wait for a view that needs them, and the tiles it draws are
// those of a replica that contours everything. With levels of detail, a distant view of the replica draws far fewer
// triangles and the same picture within a stated tolerance.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include "app/scene/run_scene.hpp"
#include "app/scene/session_spec.hpp"
#include "app/session/cluster/cluster_replica.hpp"
#include "app/support/assets.hpp"
#include "cluster_replica_helpers.hpp"
#include "compute/contour/contour_dual.hpp"
#include "cube_off.hpp"
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

constexpr double kViewEdgeX = -0.03;  // the view sees x <= this, m

// Two grooves across the bunny, far apart: one at the left end (x -0.09 .. -0.05), one at the right (0.04 .. 0.08),
// the tool lifted between them.
FrameMessage two_grooves() {
    FrameMessage m;
    compute::JournalRecord r;
    r.kind = compute::JournalKind::kBatch;
    auto add = [&](double x, ToolOp op) {
        ToolSample s;
        s.t_s = static_cast<double>(r.samples.size()) * 1e-3;
        s.position = Vec3(x, 0.0, 0.05);
        s.tool.radius_m = 0.008;
        s.op = op;
        r.samples.push_back(s);
    };
    for (int i = 0; i <= 20; ++i) add(-0.09 + 0.04 * i / 20.0, ToolOp::kSubtract);
    add(0.04, ToolOp::kNone);
    for (int i = 0; i <= 20; ++i) add(0.04 + 0.04 * i / 20.0, ToolOp::kSubtract);
    m.records.push_back(r);
    return m;
}

// Everything with x <= kViewEdgeX (a frustum whose other five planes hold every point).
renderer::Frustum left_end() {
    renderer::Frustum f;
    for (glm::dvec4& p : f.planes) p = glm::dvec4(0.0, 0.0, 0.0, 1.0);
    f.planes[0] = glm::dvec4(-1.0, 0.0, 0.0, kViewEdgeX);
    return f;
}

TEST(ClusterReplica, ContoursOnlyTheChangedTilesItsViewsNeedAndTheRestLater) {
    const std::string json = bunny_spec_json(96);
    ClusterReplica viewed(json), all(json);
    ASSERT_EQ(viewed.digest(), all.digest());
    const std::uint64_t first = viewed.tiles_contoured();
    EXPECT_GT(first, 0u);

    const FrameMessage m = two_grooves();
    viewed.apply(m);
    all.apply(m);
    ASSERT_EQ(viewed.digest(), all.digest());
    const renderer::Frustum frusta[] = {left_end()};
    viewed.contour(frusta);
    all.contour();
    const std::uint64_t partly = viewed.tiles_contoured() - first;
    const std::uint64_t whole = all.tiles_contoured() - first;
    std::printf("[cluster replica] the grooves changed %llu tiles; a view of the left end contoured %llu and left %zu\n",
                static_cast<unsigned long long>(whole), static_cast<unsigned long long>(partly), viewed.tiles_deferred());
    EXPECT_GT(viewed.tiles_deferred(), 0u);
    EXPECT_LT(partly, whole);
    EXPECT_EQ(partly + viewed.tiles_deferred(), whole);

    // Every tile the view can see is the same as the full replica's.
    const compute::Lattice& l = viewed.workpiece().model.lattice;
    const compute::TileGrid& g = viewed.workpiece().model.tiles;
    constexpr int kT = compute::TileGrid::kTileCells;
    int seen = 0;
    for (int tz = 0; tz < g.tiles[2]; ++tz)
        for (int ty = 0; ty < g.tiles[1]; ++ty)
            for (int tx = 0; tx < g.tiles[0]; ++tx) {
                const double hi_x = l.to_world(Vec3((tx + 1) * kT + 1, 0, 0)).x;
                if (hi_x > kViewEdgeX) continue;  // not wholly within the view
                const std::size_t t = g.index(tx, ty, tz);
                const TriMesh a = viewed.contourer().tile_mesh(t), b = all.contourer().tile_mesh(t);
                EXPECT_EQ(a.positions, b.positions) << "tile " << t;
                EXPECT_EQ(a.triangles, b.triangles) << "tile " << t;
                ++seen;
            }
    EXPECT_GT(seen, 0);

    // A view of everything contours the rest: the same mesh as the replica that contoured every change at once.
    viewed.contour();
    EXPECT_EQ(viewed.tiles_deferred(), 0u);
    expect_same_contour(viewed, all);
}

// A replica with levels of detail (groups contoured from the dexels at any size, as the config's "lod": "coarse") and
// one without, both carved by the same grooves: once the worker's levels are in, the wall seen from 3 m draws at
// least a third fewer workpiece triangles with levels than without, and the two pictures differ on at most 1 % of the
// pixels by more than 24 levels (a level's error is under a pixel; what differs is shading).
TEST(ClusterReplica, LevelsOfDetailDrawFewerTrianglesAndTheSamePicture) {
    const std::string json = bunny_spec_json(128);
    ClusterReplica lod(json, lod_choice("coarse")), full(json);
    const FrameMessage m0 = two_grooves();
    lod.apply(m0);
    full.apply(m0);
    ASSERT_EQ(lod.digest(), full.digest());
    full.contour();
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    do {
        lod.contour();
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    } while (lod.lod_pending() > 0 && std::chrono::steady_clock::now() < until);
    // The groups' coarse levels are rebuilt once no tile has changed for a quarter second.
    std::this_thread::sleep_for(std::chrono::milliseconds(600));
    for (int i = 0; i < 20; ++i) {
        lod.contour();
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ASSERT_EQ(lod.lod_pending(), 0u) << "the start-up levels never arrived";
    EXPECT_EQ(full.lod_pending(), 0u);

    const FrameMessage m = wall_frame(8.0);  // the bunny, 8 times its size, on the wall
    const ClusterViewport wall = small_wall();
    gpu::ContextOptions gopt;
    gopt.validation = true;
    gpu::Context ctx = gpu::Context::create(gopt);
    std::size_t triangles[2] = {0, 0};
    renderer::Image images[2];
    int k = 0;
    for (ClusterReplica* r : {&lod, &full}) {
        auto rend = renderer::OffscreenStereoRenderer::create(ctx, wall.width_px, wall.height_px);
        renderer::OffscreenSink sink(ctx, renderer::SinkOptions{renderer::StereoOutput::kMono, false,
                                                                renderer::AnaglyphMethod::kDubois, 60.0});
        (void)sink.draw(rend, r->view(m), ClusterReplica::camera(wall, m));
        (void)sink.present(rend);
        const renderer::FrameStats& st = rend.last_frame_stats();
        triangles[k] = st.tile_triangles[0];
        const fs::path dir = fs::path(testing::TempDir()) / (k == 0 ? "tridex_replica_lod" : "tridex_replica_full");
        fs::create_directories(dir);
        (void)sink.finish(rend, dir.string());
        images[k] = renderer::read_png((dir / "left.png").string());
        ++k;
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
    const renderer::ImageComparison cmp = renderer::compare_images(images[0], images[1], 24);
    std::printf("[cluster replica lod] triangles %zu with levels, %zu without; %zu of %zu pixels over 24 levels off\n",
                triangles[0], triangles[1], cmp.pixels - cmp.within, cmp.pixels);
    EXPECT_GT(triangles[1], 0u);
    EXPECT_LT(triangles[0] * 3, triangles[1] * 2);
    EXPECT_LE((cmp.pixels - cmp.within) * 100, cmp.pixels) << cmp.max_channel_diff;
}

// A coarse-first replica given a view of the left end: the left groove is contoured with the start-up tiles of the
// depth-1 groups it reaches; the right one, which no view needs, waits, and so do start-up's tiles beside it, frame
// after frame (they neither spread nor arrive before they are contoured). A view of everything contours it, and
// finishing the start-up gives the contour of a replica that contoured everything at once, bit for bit.
TEST(ClusterReplica, CoarseFirstLeavesAChangeNoViewNeedsWaitingWithStartUpsTilesBesideIt) {
    const std::string json = bunny_spec_json(256);  // the grooves' depth-1 groups and their neighbours lie apart
    ClusterReplica coarse(json, lod_choice("coarse"), nullptr, {.coarse_first = true}), full(json);
    const std::size_t at_start = coarse.startup_pending();
    const FrameMessage m = two_grooves();
    coarse.apply(m);
    full.apply(m);
    full.contour();
    const renderer::Frustum frusta[] = {left_end()};
    coarse.contour(frusta);
    const std::size_t pending = coarse.startup_pending(), deferred = coarse.tiles_deferred();
    std::printf(
        "[cluster replica coarse first] a view of the left end: %zu of %zu start-up tiles contoured, %zu changed "
        "tiles wait\n",
        at_start - pending, at_start, deferred);
    EXPECT_GT(deferred, 0u);
    EXPECT_LT(pending, at_start);
    EXPECT_GT(pending, 0u);
    for (int i = 0; i < 5; ++i) {
        coarse.contour(frusta);
        EXPECT_EQ(coarse.startup_pending(), pending)
            << "frame " << i << ": start-up's tiles spread from a waiting change";
        EXPECT_EQ(coarse.tiles_deferred(), deferred);
    }
    coarse.contour();
    EXPECT_EQ(coarse.tiles_deferred(), 0u);
    EXPECT_LT(coarse.startup_pending(), pending) << "the right groove brought no start-up tile";
    coarse.finish_contour();
    EXPECT_EQ(coarse.startup_pending(), 0u);
    expect_same_contour(coarse, full);
}

// A coarse-first replica (the config's "startup": "coarse") contours no tile before its first view, which draws the
// coarsest group levels. Drawn frame by frame with the groups each frame wants finer handed back (as a render rank
// does):
// - the bunny at four times its size, after 60 frames of a stroke at its tail that changes tiles in every frame and
//   then until five frames in a row want no detail and no coarse level waits: only the stroke's tiles are contoured,
//   and the picture is as close to a replica that contoured everything without levels as one that did so with levels
//   (at most 1.5 times its pixels more than 24 levels off, plus 20): the start-up error estimates see the thin ears
//   the coarser strides miss;
// - at 24 times its size (up close), until five frames in a row want no detail and no coarse level waits: the frames
//   want tiles, which are contoured, and the pictures agree within the previous test's tolerance;
// and finishing its start-up gives the whole replica's contour bit for bit.
TEST(ClusterReplica, CoarseFirstDrawsTheCoarsestLevelsAtOnceAndContoursWhatFramesWant) {
    const std::string json = bunny_spec_json(128);
    ClusterReplica coarse(json, lod_choice("coarse"), nullptr, {.coarse_first = true}), lod(json, lod_choice("coarse")),
        full(json);
    ASSERT_TRUE(coarse.started_coarse());
    EXPECT_FALSE(lod.started_coarse());
    EXPECT_EQ(coarse.tiles_contoured(), 0u);
    const std::size_t at_start = coarse.startup_pending();
    EXPECT_GT(at_start, 0u);

    FrameMessage m = wall_frame(24.0);
    const ClusterViewport wall = small_wall();
    gpu::ContextOptions gopt;
    gopt.validation = true;
    gpu::Context ctx = gpu::Context::create(gopt);
    auto rend = renderer::OffscreenStereoRenderer::create(ctx, wall.width_px, wall.height_px);
    renderer::OffscreenSink sink(
        ctx, renderer::SinkOptions{renderer::StereoOutput::kMono, false, renderer::AnaglyphMethod::kDubois, 60.0});
    const auto draw = [&](const ClusterReplica& r) -> const renderer::FrameStats& {
        (void)sink.draw(rend, r.view(m), ClusterReplica::camera(wall, m));
        (void)sink.present(rend);
        return rend.last_frame_stats();
    };
    const auto picture = [&](const ClusterReplica& r, const std::string& name) {
        (void)draw(r);
        const fs::path dir = fs::path(testing::TempDir()) / ("tridex_replica_" + name);
        fs::create_directories(dir);
        (void)sink.finish(rend, dir.string());
        return renderer::read_png((dir / "left.png").string());
    };
    const auto off = [](const renderer::Image& a, const renderer::Image& b) {
        const renderer::ImageComparison c = renderer::compare_images(a, b, 24);
        return c.pixels - c.within;
    };
    // Frames, each wanting detail handed back, until five in a row want none and no coarse level waits (at most
    // 60 s); how many frames.
    const auto settle = [&] {
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        int frames = 0;
        for (int quiet = 0; quiet < 5 && std::chrono::steady_clock::now() < until; ++frames) {
            const renderer::FrameStats& st = draw(coarse);
            quiet = st.groups_wanting_detail.empty() && coarse.coarse_levels_waiting() == 0 ? quiet + 1 : 0;
            coarse.want_detail(st.groups_wanting_detail);
            coarse.contour();
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return frames;
    };
    // The replica with levels from its whole contour: contoured until the worker's levels and its coarse levels are
    // in (at most 60 s).
    const auto settle_levels = [](ClusterReplica& r) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        do {
            r.contour();
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        } while ((r.lod_pending() > 0 || r.coarse_levels_waiting() > 0) && std::chrono::steady_clock::now() < until);
        ASSERT_EQ(r.lod_pending(), 0u) << "the levels never arrived";
    };
    settle_levels(lod);

    m.nav_scale = 24.0;
    EXPECT_GT(draw(coarse).groups_wanting_detail.size(), 0u) << "the coarsest levels up close are over the pixel bound";
    m.nav_scale = 4.0;
    // A stroke at the bunny's tail, a few samples a frame for 60 frames, so that tiles change in every frame.
    for (int i = 0; i < 60; ++i) {
        FrameMessage step;
        compute::JournalRecord r;
        r.kind = compute::JournalKind::kBatch;
        for (int k = 0; k < 3; ++k) {
            ToolSample sample;
            sample.t_s = (3 * i + k) * 1e-3;
            sample.position = Vec3(-0.07 + 0.02 * (3 * i + k) / 180.0, 0.0, 0.05);
            sample.tool.radius_m = 0.006;
            sample.op = ToolOp::kSubtract;
            r.samples.push_back(sample);
        }
        step.records.push_back(r);
        coarse.apply(step);
        full.apply(step);
        lod.apply(step);
        const renderer::FrameStats& st = draw(coarse);
        coarse.want_detail(st.groups_wanting_detail);
        coarse.contour();
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ASSERT_EQ(coarse.digest(), full.digest());
    full.contour();
    settle_levels(lod);
    const int far_frames = settle();
    const std::size_t far_pending = coarse.startup_pending();
    const renderer::Image far_full = picture(full, "far_whole");
    const std::size_t far_off = off(picture(coarse, "far_coarse_first"), far_full);
    const std::size_t far_lod_off = off(picture(lod, "far_levels"), far_full);
    m.nav_scale = 24.0;
    const int near_frames = settle();
    const std::size_t near_pending = coarse.startup_pending();
    std::printf(
        "[cluster replica coarse first] tiles waiting: %zu at start, %zu after a stroke and %d frames at 4 "
        "times the size (%zu pixels over 24 levels off, levels from the whole contour %zu), %zu after %d frames "
        "at 24 times\n",
        at_start, far_pending, far_frames, far_off, far_lod_off, near_pending, near_frames);
    EXPECT_GT(far_pending, 0u) << "the stroke's tiles came with it, the rest waits";
    EXPECT_LE(far_off, far_lod_off * 3 / 2 + 20);
    EXPECT_GT(far_pending, near_pending);
    EXPECT_LT(far_frames, 3000) << "at four times the size the frames never stopped wanting detail";
    EXPECT_LT(near_frames, 3000) << "up close the frames never stopped wanting detail";
    EXPECT_EQ(draw(coarse).groups_wanting_detail.size(), 0u);

    (void)settle();
    EXPECT_EQ(draw(coarse).groups_wanting_detail.size(), 0u);
    const std::size_t near_off = off(picture(coarse, "near_coarse_first"), picture(full, "near_whole"));
    EXPECT_EQ(ctx.validation_messages(), 0u);
    std::printf("[cluster replica coarse first] up close, carved: %zu of %d pixels over 24 levels off\n", near_off,
                wall.width_px * wall.height_px);
    EXPECT_LE(near_off * 100, static_cast<std::size_t>(wall.width_px * wall.height_px));

    coarse.finish_contour();
    EXPECT_EQ(coarse.startup_pending(), 0u);
    expect_same_contour(coarse, full);
}

}  // namespace
}  // namespace tridex::app

namespace tridex::app {
namespace {

// A render rank draws rank 0's reference objects, placed by their poses; one whose mesh this machine lacks is named
// and left out, and the wall goes on.
TEST(ClusterReplica, DrawsTheSessionsReferenceObjectsAndNamesOneItCannotLoad) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-replica-references";
    fs::remove_all(dir);
    fs::create_directories(dir);
    test::write_cube_off(dir / "cube.off");
    SessionSpec spec = RunScene::default_spec();
    spec.mesh_path = default_mesh_path();
    spec.resolution = 32;
    ReferenceSpec cube;
    cube.name = "stand";
    cube.mesh_path = (dir / "cube.off").string();
    cube.size_m = 0.04;
    cube.position_m = Vec3(0.1, 0.0, 0.05);
    spec.references.push_back(cube);
    ReferenceSpec lost = cube;
    lost.name = "lost";
    lost.mesh_path = (dir / "nowhere.off").string();
    spec.references.push_back(lost);
    const ClusterReplica replica(spec_to_json(spec));
    const renderer::SceneView v = replica.view(FrameMessage{});
    ASSERT_EQ(v.objects.size(), 1u);
    ASSERT_NE(v.objects[0].mesh, nullptr);
    EXPECT_EQ(v.objects[0].mesh->triangles.size(), 12u);
    EXPECT_NEAR(v.objects[0].mesh->bounds().size().x, 0.04, 1e-12);  // placed at size_m
    EXPECT_FLOAT_EQ(v.objects[0].world_from_model[3][0], 0.1f);      // at its position
    ASSERT_EQ(replica.reference_notes().size(), 1u);
    EXPECT_NE(replica.reference_notes()[0].find("reference 'lost' not drawn here: "), std::string::npos)
        << replica.reference_notes()[0];
}

}  // namespace
}  // namespace tridex::app
