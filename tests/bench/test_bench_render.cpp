// Smoke test of `tridex bench --render` (bench/bench_render): a tiny run writes render_bench.json with one
// row per (N, size, view, setting: LOD + culling, culling, neither, each with ambient occlusion on, and LOD +
// culling and culling with it off) and the documented fields, with consistent tile and triangle counts, and the
// LOD comparison images.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <tuple>

#include "app/scene/workpiece_source.hpp"
#include "bench/bench_render.hpp"
#include "bench/bench_render_gpu.hpp"
#include "core/error.hpp"

namespace tridex::bench {
namespace {

std::string bunny() {
    const char* assets = std::getenv("TRIDEX_ASSETS");
    return (std::filesystem::path(assets ? assets : "assets") / "bunny.off").string();
}

TEST(BenchRender, TinyRunWritesOneRowPerViewAndSettingWithAllFields) {
    RenderBenchOptions o;
    o.mesh = bunny();
    o.resolutions = {48};
    o.sizes = {{96, 72}};
    o.frames = 2;
    o.out = (std::filesystem::temp_directory_path() / "tridex_test_bench_render").string();
    std::filesystem::remove_all(o.out);
    const std::vector<RenderBenchRow> rows = run_render_bench(o);
    ASSERT_EQ(rows.size(), 10u);

    std::ifstream f(std::filesystem::path(o.out) / "render_bench.json");
    ASSERT_TRUE(f.good());
    const nlohmann::json j = nlohmann::json::parse(f);
    ASSERT_TRUE(j.is_array());
    ASSERT_EQ(j.size(), 10u);
    std::set<std::tuple<std::string, bool, std::string, std::string>> seen;
    for (std::size_t i = 0; i < j.size(); ++i) {
        const nlohmann::json& r = j[i];
        for (const char* key : {"n", "width", "height", "view", "culling", "frame_ms_median", "frame_ms_p99",
                                "gpu_frame_ms_median", "passes", "tiles_drawn_left", "tiles_drawn_right",
                                "tiles_skipped_left", "tiles_skipped_right", "tiles", "triangles", "speedup", "lod",
                                "triangles_drawn", "lod_speedup", "silhouette_mismatch", "mean_abs_diff",
                                "tile_buffers", "tile_memory_blocks", "ao", "draws", "draws_merged"})
            ASSERT_TRUE(r.contains(key)) << "row " << i << " lacks " << key;
        // Tiles drawn: at least one draw recorded, and the merged-away draws never exceed the tiles' draws.
        EXPECT_GE(r["draws"].get<std::size_t>(), 1u);
        EXPECT_LE(r["draws_merged"].get<std::size_t>(),
                  r["tiles_drawn_left"].get<std::size_t>() + r["tiles_drawn_right"].get<std::size_t>());
        EXPECT_EQ(r["n"].get<int>(), 48);
        EXPECT_EQ(r["width"].get<int>(), 96);
        EXPECT_EQ(r["height"].get<int>(), 72);
        seen.insert({r["view"].get<std::string>(), r["culling"].get<bool>(), r["lod"].get<std::string>(),
                     r["ao"].get<std::string>()});
        const bool lod = r["lod"].get<std::string>() == "on";
        // Triangles drawn per eye: all of them without LOD in the whole view, fewer with LOD (the bunny is far
        // smaller than a pixel per cell at N = 48 in a 96x72 image).
        const auto drawn_left = r["triangles_drawn"][0].get<std::size_t>();
        if (r["view"] == "whole" && !lod) {
            EXPECT_EQ(drawn_left, rows[0].triangles);
        }
        if (lod) {
            EXPECT_LT(drawn_left, rows[0].triangles);
            EXPECT_GT(r["lod_speedup"].get<double>(), 0.0);
            EXPECT_GE(r["silhouette_mismatch"].get<double>(), 0.0);
            EXPECT_LT(r["silhouette_mismatch"].get<double>(), 0.05);
            EXPECT_GE(r["mean_abs_diff"].get<double>(), 0.0);
        } else {
            EXPECT_EQ(r["lod_speedup"].get<double>(), 0.0);
            EXPECT_EQ(r["silhouette_mismatch"].get<double>(), -1.0);
        }
        EXPECT_GT(r["frame_ms_median"].get<double>(), 0.0);
        EXPECT_GE(r["frame_ms_p99"].get<double>(), r["frame_ms_median"].get<double>());
        const auto tiles = r["tiles"].get<std::size_t>();
        EXPECT_GT(tiles, 0u);
        EXPECT_EQ(tiles, rows[0].tiles);
        EXPECT_EQ(r["triangles"].get<std::size_t>(), rows[0].triangles);
        // Vertices + indices per tile and per level of detail.
        EXPECT_GE(r["tile_buffers"].get<std::size_t>(), 2 * tiles);
        EXPECT_EQ(r["tile_buffers"].get<std::size_t>() % 2, 0u);
        EXPECT_GE(r["tile_memory_blocks"].get<std::size_t>(), 1u);   // ... sub-allocated from one pool block
        EXPECT_LE(r["tile_memory_blocks"].get<std::size_t>(), 2u);
        EXPECT_EQ(r["tiles_drawn_left"].get<std::size_t>() + r["tiles_skipped_left"].get<std::size_t>(), tiles);
        EXPECT_EQ(r["tiles_drawn_right"].get<std::size_t>() + r["tiles_skipped_right"].get<std::size_t>(), tiles);
        if (!r["culling"].get<bool>()) {
            EXPECT_EQ(r["tiles_skipped_left"].get<std::size_t>() + r["tiles_skipped_right"].get<std::size_t>(), 0u);
            EXPECT_EQ(r["speedup"].get<double>(), 0.0);
        } else if (lod) {
            EXPECT_EQ(r["speedup"].get<double>(), 0.0);
        } else if (r["ao"] == "on") {
            EXPECT_GT(r["speedup"].get<double>(), 0.0);
        } else {
            EXPECT_EQ(r["speedup"].get<double>(), 0.0);  // no unculled partner with the occlusion off
        }
        // Per-pass medians: the opaque pass always exists (GPU timestamps) or the CPU "frame" time does.
        const nlohmann::json& passes = r["passes"];
        ASSERT_TRUE(passes.is_object());
        ASSERT_TRUE(passes.contains("opaque") || passes.contains("frame")) << passes.dump();
        if (passes.contains("opaque")) {  // the occlusion is timed only on frames that ran it
            EXPECT_EQ(passes.contains("occlusion"), r["ao"] == "on") << passes.dump();
        }
        for (const auto& [name, ms] : passes.items()) EXPECT_GE(ms.get<double>(), 0.0) << name;
    }
    std::set<std::tuple<std::string, bool, std::string, std::string>> expected;
    for (const char* view : {"whole", "close-up"}) {
        for (const char* ao : {"on", "off"}) {
            expected.insert({view, true, "on", ao});
            expected.insert({view, true, "off", ao});
        }
        expected.insert({view, false, "off", "on"});
    }
    EXPECT_EQ(seen, expected);
    for (const char* png : {"render_n48_lod_on.png", "render_n48_lod_off.png", "render_n48_lod_on_ao_off.png",
                            "render_n48_lod_off_ao_off.png"})
        EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(o.out) / png)) << png;
    // The whole view sees every tile; the close-up leaves some outside at least one eye's frustum.
    for (const RenderBenchRow& r : rows) {
        if (r.view == "whole") {
            EXPECT_EQ(r.tiles_skipped_left + r.tiles_skipped_right, 0u);
        }
        if (r.view == "close-up" && r.culling) {
            EXPECT_GT(r.tiles_skipped_left + r.tiles_skipped_right, 0u);
            EXPECT_GT(r.tiles_drawn_left + r.tiles_drawn_right, 0u);
        }
    }
}

TEST(BenchRender, GpuContourFramesWithAndWithoutTheReadBackLevels) {
    gpu::Context ctx = gpu::Context::create({});
    app::Workpiece wp = app::prepare_workpiece(bunny(), 64, 0.3, Vec3(0.0, 0.0, 0.3));
    Pose head;
    head.position = Vec3(0.0, 0.15, 0.65);
    const GpuContourLodTiming t = time_gpu_contour_lod(ctx, wp, 160, 120, head, 0.064, 2);
    ASSERT_TRUE(t.ran) << t.why;  // lavapipe has shaderFloat64
    EXPECT_GT(t.tiles, 0u);
    EXPECT_GT(t.full_ms, 0.0);
    EXPECT_GT(t.levels_ms, 0.0);
    EXPECT_GT(t.full_triangles, 0u);
    EXPECT_LT(t.levels_triangles, t.full_triangles);  // coarser levels drawn for the whole view
    EXPECT_LT(t.silhouette_mismatch, 0.01);
}

TEST(BenchRender, RejectsBadOptions) {
    RenderBenchOptions o;
    o.mesh = bunny();
    o.resolutions = {48};
    o.sizes = {{96, 72}};
    o.frames = 0;
    EXPECT_THROW(run_render_bench(o), Error);
    o.frames = 1;
    o.sizes = {{8, 72}};
    EXPECT_THROW(run_render_bench(o), Error);
    o.sizes = {{96, 72}};
    o.occlusion = {};
    EXPECT_THROW(run_render_bench(o), Error);
}

}  // namespace
}  // namespace tridex::bench
