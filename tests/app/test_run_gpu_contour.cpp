// `tridex run` with GPU contouring (the default when sculpting on the GPU): the sculpt thread contours dirty
// tiles on the GPU into buffers the stereo renderer draws with indirect draws, the haptic loop still gets its
// active surfaces, report.json says which contour path ran with the GPU contour's counters; --cpu-contour and
// --cpu keep the CPU tile-mesh path; the images of both paths agree within the stated tolerance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "test_files.hpp"
#include "app/session/run/run_session.hpp"
#include "renderer/image/image.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

RunResult run_stroke(const fs::path& dir, const std::string& name, bool cpu, bool cpu_contour) {
    RunOptions o;
    o.scene = test::write_small_scene(dir, 0.8);
    o.display = "offscreen";
    o.stereo = "side-by-side";
    o.out = (dir / name).string();  // until the stroke ends
    o.cpu = cpu;
    o.gpu = !cpu;  // the GPU path forced: on lavapipe the device's type alone would choose the CPU pool
    o.cpu_contour = cpu_contour;
    o.gpu_contour = !cpu && !cpu_contour;  // lavapipe's default is the CPU contour
    return run_stereo_session(o);
}

void print_run(const char* what, const RunResult& r) {
    std::printf(
        "[run %s] contour %s, sculpt %s: %llu frames, frame p50 %.2f ms, GPU p50 %.2f ms, %llu steps, "
        "boolean p50 %.2f ms, contour p50 %.2f ms, %llu tiles recontoured\n",
        what, r.contour_path.c_str(), r.sculpt_path.c_str(), static_cast<unsigned long long>(r.frames),
        r.frame_ms.percentile_ms(0.5), r.gpu_ms.percentile_ms(0.5), static_cast<unsigned long long>(r.sculpt.steps),
        r.sculpt.boolean_ms.percentile_ms(0.5), r.sculpt.contour_ms.percentile_ms(0.5),
        static_cast<unsigned long long>(r.sculpt.tiles_recontoured));
}

TEST(RunGpuContour, GpuSculptPathContoursOnTheGpuAndTheHapticLoopKeepsItsSurfaces) {
    const fs::path dir = test::temp_dir("run_gpu_contour");
    const RunResult r = run_stroke(dir, "gpu", false, false);
    print_run("gpu", r);
    ASSERT_EQ(r.sculpt_path, "gpu");  // lavapipe is there in the tests
    EXPECT_EQ(r.contour_path, "gpu");
    EXPECT_TRUE(r.stroke_completed);
    EXPECT_LT(r.volume_after_m3, r.volume_before_m3);
    // The haptic loop: every tick ran, its active surfaces kept coming (initial + one per changing step).
    EXPECT_GE(r.loop.ticks, 800u);
    EXPECT_EQ(r.loop.samples_dropped, 0u);
    EXPECT_GT(r.sculpt.steps, 0u);
    EXPECT_GE(r.sculpt.publishes, r.sculpt.steps + 1);
    // GPU contouring ran and the renderer drew it; the tiles read back from it got their levels of detail, which
    // the renderer uploaded (levels are on by default).
    EXPECT_GT(r.contour_tiles_initial, 0u);
    EXPECT_GT(r.gpu_contour.updates, 1u);
    EXPECT_GE(r.gpu_contour.tiles_gpu, r.contour_tiles_initial + r.sculpt.tiles_recontoured);
    EXPECT_GT(r.render.tile_uploads, 0u);
    EXPECT_GT(r.tiles_last, 0u);
    EXPECT_GT(r.triangles, 1000u);
    EXPECT_GE(r.mesh_versions_drawn, 2u);
    EXPECT_EQ(r.validation_messages, 0u);
    const nlohmann::json rep = test::read_json(dir / "gpu" / "report.json");
    EXPECT_EQ(rep["contour_path"], "gpu");
    EXPECT_EQ(rep["contour"]["gpu"]["tiles"].get<std::uint64_t>(), r.gpu_contour.tiles_gpu + r.gpu_contour.tiles_cpu);
    EXPECT_TRUE(rep["contour"]["gpu"].contains("host_fallback_tiles"));
    EXPECT_TRUE(rep["contour"]["gpu"].contains("pool_grows"));
    EXPECT_TRUE(rep["contour"]["gpu"].contains("lock_wait_ms_max"));
    EXPECT_GT(rep["sculpt"]["contour_ms"]["median"].get<double>(), 0.0);
    EXPECT_TRUE(rep["render"]["lod"]["on"].get<bool>());
    EXPECT_GT(rep["render"]["lod"]["tiles_built"].get<std::uint64_t>(), 0u);
    fs::remove_all(dir);
}

TEST(RunGpuContour, CpuContourAndCpuKeepTheTileMeshPath) {
    const fs::path dir = test::temp_dir("run_cpu_contour");
    for (const bool cpu : {false, true}) {
        const RunResult r = run_stroke(dir, cpu ? "cpu" : "cpu_contour", cpu, !cpu);
        print_run(cpu ? "cpu" : "cpu-contour", r);
        EXPECT_EQ(r.sculpt_path, cpu ? "cpu" : "gpu");
        EXPECT_EQ(r.contour_path, "cpu");
        EXPECT_TRUE(r.stroke_completed);
        EXPECT_GT(r.render.tile_uploads, 0u);  // CPU tile meshes went to the renderer
        EXPECT_EQ(r.gpu_contour.tiles_gpu, 0u);
        EXPECT_EQ(r.validation_messages, 0u);
        const std::string want = cpu ? "the Booleans run on the CPU" : "--cpu-contour given";
        EXPECT_TRUE(std::any_of(r.notes.begin(), r.notes.end(),
                                [&](const std::string& n) { return n.find(want) != std::string::npos; }))
            << want;
        EXPECT_EQ(r.contour_reason, want);
        const nlohmann::json rep = test::read_json(dir / (cpu ? "cpu" : "cpu_contour") / "report.json");
        EXPECT_EQ(rep["contour_path"], "cpu");
        EXPECT_EQ(rep["contour_path_reason"], want);
    }
    fs::remove_all(dir);
}

// Fraction of pixels whose "is background" differs, and mean |difference| where both show something.
struct Agreement {
    double coverage_mismatch = 0.0, mean_abs = 0.0, covered = 0.0;
};
Agreement agree(const renderer::Image& a, const renderer::Image& b) {
    const auto bg = [](const renderer::Image& im, std::size_t p) {
        return im.rgba[p * 4] < 40 && im.rgba[p * 4 + 1] < 40 && im.rgba[p * 4 + 2] < 40;
    };
    const std::size_t n = static_cast<std::size_t>(a.width) * a.height;
    std::size_t mismatch = 0, covered = 0;
    double sum = 0.0;
    for (std::size_t p = 0; p < n; ++p) {
        const bool ba = bg(a, p), bb = bg(b, p);
        mismatch += ba != bb;
        if (ba || bb) continue;
        ++covered;
        for (int c = 0; c < 3; ++c) sum += std::abs(int(a.rgba[p * 4 + c]) - int(b.rgba[p * 4 + c]));
    }
    return Agreement{static_cast<double>(mismatch) / std::max<std::size_t>(covered, 1),
                     covered ? sum / (3.0 * covered) : 0.0, static_cast<double>(covered) / n};
}

TEST(RunGpuContour, ImagesAgreeWithTheCpuContourPath) {
    // No stroke: the model and the tool at rest are the same on both paths; only the workpiece's drawing differs.
    const fs::path dir = test::temp_dir("run_gpu_contour_images");
    const std::string scene = (dir / "still.json").string();
    std::ofstream(scene) << R"({
  "workpiece": { "resolution": 48, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "display": { "preset": "desktop", "resolution": [192, 144], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.05, 0.45] }
})";
    renderer::Image img[2][2];
    for (int k = 0; k < 2; ++k) {
        RunOptions o;
        o.scene = scene;
        o.display = "offscreen";
        o.stereo = "side-by-side";
        o.frames = 3;
        o.items = false;
        o.pace = false;
        o.cpu_contour = k == 1;
        o.gpu_contour = k == 0;
        // Full resolution on both: whether a path's levels arrived within three frames is a race, and at this image
        // size a level's one-pixel error is about 1 % of the silhouette (levels: test_gpu_contour_lod.cpp).
        o.lod = "off";
        o.out = (dir / (k ? "cpu" : "gpu")).string();
        const RunResult r = run_stereo_session(o);
        EXPECT_EQ(r.contour_path, k ? "cpu" : "gpu");
        EXPECT_EQ(r.validation_messages, 0u);
        img[k][0] = renderer::read_png((dir / (k ? "cpu" : "gpu") / "left.png").string());
        img[k][1] = renderer::read_png((dir / (k ? "cpu" : "gpu") / "right.png").string());
    }
    for (int eye = 0; eye < 2; ++eye) {
        const Agreement a = agree(img[0][eye], img[1][eye]);
        std::printf("[run images] eye %d: %.1f%% covered, coverage mismatch %.3f%% of covered, mean |diff| %.2f /255\n",
                    eye, 100.0 * a.covered, 100.0 * a.coverage_mismatch, a.mean_abs);
        EXPECT_GT(a.covered, 0.05);
        EXPECT_LT(a.coverage_mismatch, 0.005);  // the same silhouette
        EXPECT_LT(a.mean_abs, 12.0);            // flat (GPU contour) vs smooth (CPU tiles) shading
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
