// Two frames in flight: draw() after draw() without waiting while tiles, the tool mesh and the overlay change every
// frame. Replaced buffers must outlive the frames that read them (the validation layer reports any buffer destroyed
// or rewritten while a submitted frame uses it), finish() gives the last frame's own timings, and the final picture is
// the one a fresh renderer draws of the same scene.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <vector>

#include "core/primitives.hpp"
#include "gpu/context.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "test_scene.hpp"

namespace tridex::renderer {
namespace {

constexpr int kW = 160, kH = 120;
constexpr int kTiles = 16;

/// A 2 cm cube at tile position i, raised by `lift` m towards the viewer.
TriMesh tile_cube(int i, double lift) {
    const Vec3 lo(-0.1 + 0.05 * (i % 4), -0.1 + 0.05 * (i / 4), -0.01 + lift);
    Aabb b;
    b.add(lo);
    b.add(lo + Vec3(0.02));
    return box_mesh(b);
}

struct Scene {
    std::vector<TriMesh> low, high;  // each tile in two shapes
    std::vector<TileMesh> tiles;
    TriMesh tools[2];
    Scene() {
        for (int i = 0; i < kTiles; ++i) {
            low.push_back(tile_cube(i, 0.0));
            high.push_back(tile_cube(i, 0.02));
        }
        for (int i = 0; i < kTiles; ++i) {
            Aabb b = low[static_cast<std::size_t>(i)].bounds();
            b.add(high[static_cast<std::size_t>(i)].bounds().hi);
            tiles.push_back(TileMesh{&low[static_cast<std::size_t>(i)], b, 0, nullptr, static_cast<std::uint64_t>(i)});
        }
        Aabb small;
        small.add(Vec3(-0.01));
        small.add(Vec3(0.01));
        tools[0] = box_mesh(small);
        tools[1] = unit_sphere(8, 16);
        for (Vec3& p : tools[1].positions) p *= 0.012;
    }
    /// Frame f: every tile whose index has the same parity as f switches shape (a new version).
    SceneView frame(int f) {
        for (int i = 0; i < kTiles; ++i)
            if ((i + f) % 2 == 0) {
                TileMesh& t = tiles[static_cast<std::size_t>(i)];
                t.mesh = (f / 2) % 2 ? &high[static_cast<std::size_t>(i)] : &low[static_cast<std::size_t>(i)];
                t.version = static_cast<std::uint64_t>(f + 1);
            }
        SceneView v;
        v.show_workspace = false;
        v.tiles = tiles;
        v.tool_shape.kind = ToolKind::kMesh;
        v.tool_mesh = &tools[(f / 3) % 2];
        v.tool_radius_m = 0.012;
        v.tool_centre_m = Vec3(0.12, 0.1, 0.05);
        v.show_overlay = true;
        v.overlay_status = "frame " + std::to_string(f);
        return v;
    }
};

TEST(FramesInFlight, ReplacedBuffersOutliveTheirFramesAndTheLastFrameIsRight) {
    gpu::Context ctx = gpu::Context::create({});
    {
        Scene s;
        const Pose head{Vec3(0.0, 0.0, 0.5)};
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH);
        constexpr int kFrames = 12;
        std::uint64_t uploads = 0;
        std::vector<double> submitted_s;  // steady clock, s: when each frame's draw() returned
        const auto steady_s = [] {
            return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
        };
        const double start_s = steady_s();
        for (int f = 0; f < kFrames; ++f) {
            uploads += r.draw(s.frame(f), test::small_screen(), head, 0.064).tile_uploads;
            submitted_s.push_back(steady_s());
        }
        EXPECT_EQ(uploads, static_cast<std::uint64_t>(kTiles + (kFrames - 1) * kTiles / 2));
        const FrameStats last = r.finish();
        // Every frame's own statistics once, oldest first (the tile uploads add up as above).
        const std::vector<FrameStats> done = r.take_finished_frames();
        ASSERT_EQ(done.size(), static_cast<std::size_t>(kFrames));
        std::uint64_t seen_uploads = 0;
        for (const FrameStats& fs : done) seen_uploads += fs.tile_uploads;
        EXPECT_EQ(seen_uploads, uploads);
        // Numbered in order; with calibrated timestamps each ended on the device after the draw() before it was
        // called, in order, and before finish() returned.
        const double end_s = steady_s();
        for (std::size_t k = 0; k < done.size(); ++k) {
            EXPECT_EQ(done[k].frame, k + 1);
            if (!ctx.features().calibrated_timestamps || !r.gpu_timestamps_available()) continue;
            ASSERT_TRUE(std::isfinite(done[k].gpu_end_s)) << k;
            EXPECT_GT(done[k].gpu_end_s, k == 0 ? start_s : submitted_s[k - 1]) << k;
            EXPECT_LT(done[k].gpu_end_s, end_s) << k;
            if (k > 0) {
                EXPECT_GE(done[k].gpu_end_s, done[k - 1].gpu_end_s) << k;
            }
        }
        EXPECT_TRUE(r.take_finished_frames().empty());
        EXPECT_EQ(r.frames_rendered(), static_cast<std::uint64_t>(kFrames));
        if (r.gpu_timestamps_available()) {
            EXPECT_GT(last.frame_ms, 0.0);
        }
        EXPECT_EQ(ctx.validation_messages(), 0u);

        // The frame after, drawn and read back here and by a fresh renderer: the same pixels.
        const SceneView v = s.frame(kFrames);
        OffscreenStereoRenderer fresh = OffscreenStereoRenderer::create(ctx, kW, kH);
        SceneView same = v;
        same.frame_time_ms = 1.0;  // the overlay shows a frame time: make both show the same
        const StereoImages a = r.render(same, test::small_screen(), head, 0.064);
        const StereoImages b = fresh.render(same, test::small_screen(), head, 0.064);
        EXPECT_EQ(compare_images(a.left, b.left, 0).within, static_cast<std::size_t>(kW * kH));
        EXPECT_EQ(compare_images(a.right, b.right, 0).within, static_cast<std::size_t>(kW * kH));
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
