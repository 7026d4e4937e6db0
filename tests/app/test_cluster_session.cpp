// A cluster session on this machine, as mpirun starts it on a wall's PCs: three ranks offscreen (rank 0 the session,
// ranks 1 and 2 each half of the wall). Their tiles stitched together equal the wall drawn whole on one machine from
// rank 0's journal, the models agree at every check, and a render rank that dies or hangs ends the session in order
// with its work kept.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "../renderer/test_window_xvfb.hpp"
#include "../test_paths.hpp"
#include "app/session/cluster/cluster_replica.hpp"
#include "cluster_launch.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/model/model_digest.hpp"
#include "gpu/context.hpp"
#include "renderer/image/image.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/output/offscreen_sink.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

using test::cluster_data;
using test::have_mpirun;
using test::Launch;
using test::mpirun3;

nlohmann::json read_json(const fs::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in);
}

Vec3 v3(const nlohmann::json& j) { return Vec3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>()); }
Quat q4(const nlohmann::json& j) { return Quat(j[0].get<double>(), j[1].get<double>(), j[2].get<double>(), j[3].get<double>()); }


TEST(ClusterSession, ThreeRanksDrawTheWallOneMachineDraws) {
    if (!have_mpirun()) GTEST_SKIP() << "mpirun is not installed (Debian's openmpi-bin; scripts/install-deps.sh installs it)";
    const fs::path out = fs::path(testing::TempDir()) / "tridex_cluster_ok";
    const Launch l = mpirun3(out, cluster_data() / "two_tiles.json");
    ASSERT_EQ(l.exit_code, 0) << l.log;
    const nlohmann::json report = read_json(out / "report.json");
    const nlohmann::json& c = report["cluster"];
    ASSERT_TRUE(c.is_object()) << report.dump(1);
    EXPECT_TRUE(c["failure"].is_null()) << c["failure"];
    EXPECT_EQ(c["ranks"], 3);
    EXPECT_GE(c["checks"].get<int>(), 2) << "the models were compared at least at one frame and at the end";
    ASSERT_EQ(c["render_ranks"].size(), 2u);

    // The whole wall drawn on this one machine: rank 0's journal applied to the same workpiece, the last frame's view.
    const compute::Journal journal = compute::read_journal((out / "session.tdj").string());
    ClusterReplica one(journal.session);
    FrameMessage m;
    m.records = journal.records;
    ASSERT_FALSE(one.apply(m).has_value());
    one.contour();
    for (const nlohmann::json& rank : c["render_ranks"]) {
        EXPECT_EQ(rank["final_digest"].get<std::uint64_t>(), one.digest()) << "rank " << rank["rank"];
        EXPECT_EQ(rank["validation_messages"], 0);
        EXPECT_EQ(rank["lod"], "off") << "the stitched images are compared with one drawn at full resolution";
    }
    const nlohmann::json& last = c["render_ranks"][0]["last_frame"];
    m.head = Pose{v3(last["head_m"]), q4(last["head_orientation"])};
    m.nav_pose = Pose{v3(last["nav_m"]), q4(last["nav_orientation"])};
    m.nav_scale = last["nav_scale"];
    m.eye_separation_m = last["eye_separation_m"];
    m.show_tool = last["show_tool"];
    m.tool_m = v3(last["tool_m"]);
    m.tool_orientation = q4(last["tool_orientation"]);
    m.tool.radius_m = last["tool_radius_m"];
    m.ao = last["ao"];
    ClusterViewport whole;
    whole.name = "whole";
    whole.screen = renderer::Screen{Vec3(-1.524, 0.60, 0.0), Vec3(1.524, 0.60, 0.0), Vec3(-1.524, 2.886, 0.0)};
    whole.width_px = 320;
    whole.height_px = 240;
    whole.stereo = renderer::StereoOutput::kSideBySide;
    gpu::ContextOptions gopt;
    gopt.validation = true;
    gpu::Context ctx = gpu::Context::create(gopt);
    auto rend = renderer::OffscreenStereoRenderer::create(ctx, whole.width_px, whole.height_px);
    renderer::OffscreenSink sink(ctx, renderer::SinkOptions{whole.stereo, false, renderer::AnaglyphMethod::kDubois, 60.0});
    (void)sink.draw(rend, one.view(m), ClusterReplica::camera(whole, m));
    (void)sink.present(rend);
    const fs::path ref_dir = out / "one-machine";
    fs::create_directories(ref_dir);
    (void)sink.finish(rend, ref_dir.string());
    EXPECT_EQ(ctx.validation_messages(), 0u);

    for (const char* eye : {"left.png", "right.png"}) {
        const renderer::Image a = renderer::read_png((out / "left-half" / eye).string());
        const renderer::Image b = renderer::read_png((out / "right-half" / eye).string());
        const renderer::Image ref = renderer::read_png((ref_dir / eye).string());
        ASSERT_EQ(a.width + b.width, ref.width);
        renderer::Image stitched = renderer::Image::filled(ref.width, ref.height, 0, 0, 0);
        for (int y = 0; y < ref.height; ++y) {
            std::memcpy(stitched.at(0, y), a.at(0, y), static_cast<std::size_t>(a.width) * 4);
            std::memcpy(stitched.at(a.width, y), b.at(0, y), static_cast<std::size_t>(b.width) * 4);
        }
        renderer::write_png((out / (std::string("stitched_") + eye)).string(), stitched);
        // Ambient occlusion reads neighbouring pixels, which a tile's edge cuts off: a few pixels along the seam may
        // differ by a little; everything else is the same image.
        const renderer::ImageComparison cmp = renderer::compare_images(stitched, ref, 8);
        std::size_t off_seam = 0;  // pixels more than 8 levels off, further than 3 pixels from the seam
        for (int y = 0; y < ref.height; ++y)
            for (int x = 0; x < ref.width; ++x) {
                if (std::abs(x - a.width) <= 3) continue;
                const std::uint8_t* p = stitched.at(x, y);
                const std::uint8_t* q = ref.at(x, y);
                for (int k = 0; k < 3; ++k)
                    if (std::abs(p[k] - q[k]) > 8) {
                        ++off_seam;
                        break;
                    }
            }
        EXPECT_EQ(off_seam, 0u) << eye << ": pixels away from the seam differ";
        EXPECT_GE(cmp.fraction_within(), 0.995) << eye << ": " << cmp.pixels - cmp.within << " pixels differ by more than 8";
        const renderer::ImageComparison exact = renderer::compare_images(stitched, ref, 0);
        std::printf("%s: %zu of %zu pixels equal, %zu within 8 levels, largest difference %d\n", eye, exact.within,
                    exact.pixels, cmp.within, cmp.max_channel_diff);
    }
}

TEST(ClusterSession, ARenderRankThatDiesEndsTheSessionAndKeepsItsWork) {
    if (!have_mpirun()) GTEST_SKIP() << "mpirun is not installed (Debian's openmpi-bin; scripts/install-deps.sh installs it)";
    const fs::path out = fs::path(testing::TempDir()) / "tridex_cluster_dies";
    const Launch l = mpirun3(out, cluster_data() / "two_tiles_quick_timeout.json", "TRIDEX_CLUSTER_FAULT=2:3:exit");
    EXPECT_EQ(l.exit_code, 5) << l.log;  // rank 0 kept its work, then ended every rank with 5
    EXPECT_NE(l.log.find("render rank 2 did not answer frame "), std::string::npos) << l.log;
    EXPECT_NE(l.log.find("kept its work"), std::string::npos) << l.log;
    const nlohmann::json report = read_json(out / "report.json");
    EXPECT_NE(report["cluster"]["failure"].get<std::string>().find("render rank 2"), std::string::npos);
    EXPECT_TRUE(fs::exists(out / "session.tdj"));
    EXPECT_TRUE(fs::exists(out / "sculpted.ply"));
    // Nothing sculpted is lost: the journal holds every sample the session applied.
    const compute::Journal journal = compute::read_journal((out / "session.tdj").string());
    std::size_t samples = 0;
    for (const compute::JournalRecord& r : journal.records) samples += r.samples.size();
    EXPECT_EQ(samples, report["sculpt"]["samples"].get<std::size_t>());
}

TEST(ClusterSession, ARenderRankThatHangsIsNamedWithinTheTimeout) {
    if (!have_mpirun()) GTEST_SKIP() << "mpirun is not installed (Debian's openmpi-bin; scripts/install-deps.sh installs it)";
    const fs::path out = fs::path(testing::TempDir()) / "tridex_cluster_hangs";
    const Launch l = mpirun3(out, cluster_data() / "two_tiles_quick_timeout.json", "TRIDEX_CLUSTER_FAULT=1:2:hang");
    EXPECT_EQ(l.exit_code, 5) << l.log;  // rank 0 kept its work, then ended every rank with 5
    EXPECT_NE(l.log.find("render rank 1 did not answer frame "), std::string::npos) << l.log;
    EXPECT_NE(l.log.find("within 5 s"), std::string::npos) << l.log;
    EXPECT_TRUE(fs::exists(out / "report.json"));
}

// A render rank's viewport in a window on its own X display (a private Xvfb): it opens, presents every frame in step
// and closes with the session; the other rank's offscreen tile is written as before.
TEST(ClusterSession, AWindowViewportPresentsEveryFrameOnItsDisplay) {
    if (!have_mpirun()) GTEST_SKIP() << "mpirun is not installed (Debian's openmpi-bin; scripts/install-deps.sh installs it)";
    if (std::system("command -v Xvfb > /dev/null 2>&1") != 0) GTEST_SKIP() << "needs Xvfb (scripts/install-deps.sh installs xvfb)";
    renderer::test::VirtualDisplay display(640, 480);
    const fs::path out = fs::path(testing::TempDir()) / "tridex_cluster_window";
    const Launch l = mpirun3(out, cluster_data() / "window_tile.json");
    ASSERT_EQ(l.exit_code, 0) << l.log;
    const nlohmann::json c = read_json(out / "report.json")["cluster"];
    ASSERT_EQ(c["render_ranks"].size(), 2u) << c.dump(1);
    const nlohmann::json& win = c["render_ranks"][0];
    EXPECT_EQ(win["rank"], 1);
    EXPECT_GT(win["presents"].get<int>(), 0);
    EXPECT_EQ(win["presents"], win["frames"]);
    EXPECT_EQ(win["frames"], c["frames"]);
    EXPECT_EQ(win["validation_messages"], 0);
    EXPECT_TRUE(win["files"].empty()) << "a window viewport writes no images";
    for (const nlohmann::json& rank : c["render_ranks"]) {  // the config's default: levels of detail on
        EXPECT_EQ(rank["lod"], "on");
        EXPECT_GT(rank["tile_triangles_last_frame"].get<long>(), 0);
    }
    EXPECT_TRUE(fs::exists(out / "right-half" / "left.png"));
    EXPECT_FALSE(fs::exists(out / "left-window"));
}

TEST(ClusterSession, AReplicaThatDivergesIsCaughtByTheDigestCheck) {
    if (!have_mpirun()) GTEST_SKIP() << "mpirun is not installed (Debian's openmpi-bin; scripts/install-deps.sh installs it)";
    const fs::path out = fs::path(testing::TempDir()) / "tridex_cluster_diverges";
    const Launch l = mpirun3(out, cluster_data() / "two_tiles_quick_timeout.json", "TRIDEX_CLUSTER_FAULT=2:1:diverge");
    EXPECT_EQ(l.exit_code, 5) << l.log;  // rank 0 kept its work, then ended every rank with 5
    EXPECT_NE(l.log.find("render rank 2 holds another model than rank 0 at frame "), std::string::npos) << l.log;
    const nlohmann::json report = read_json(out / "report.json");
    EXPECT_NE(report["cluster"]["failure"].get<std::string>().find("replicas diverged"), std::string::npos);
    EXPECT_TRUE(fs::exists(out / "session.tdj"));
}

}  // namespace
}  // namespace tridex::app
