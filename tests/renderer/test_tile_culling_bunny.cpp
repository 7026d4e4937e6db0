// Benchmark: a 1280x720 stereo frame of the bunny contoured at 256 cells, drawn as per-tile meshes with and
// without per-eye tile culling, timed per pass; culling must not change a single pixel.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/mesh/mesh_io.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/tridexel.hpp"
#include "compute/model/workpiece.hpp"
#include "gpu/context.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::renderer {
namespace {

// The contoured mesh cut into the contouring's 16^3-cell tiles (each triangle to the tile holding its
// centroid), with each tile's own vertices and exact bounds.
struct Tiles {
    std::vector<TriMesh> meshes;
    std::vector<TileMesh> list;
};

Tiles split_into_tiles(const TriMesh& mesh, const compute::Lattice& lattice) {
    std::map<std::array<int, 3>, std::vector<std::size_t>> by_tile;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        const Vec3 c = (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) / 3.0;
        const Vec3 g = lattice.to_grid(c) / double(compute::TileGrid::kTileCells);
        by_tile[{int(std::floor(g.x)), int(std::floor(g.y)), int(std::floor(g.z))}].push_back(t);
    }
    Tiles out;
    out.meshes.reserve(by_tile.size());
    for (const auto& [key, tris] : by_tile) {
        TriMesh m;
        std::map<std::uint32_t, std::uint32_t> remap;
        for (std::size_t t : tris) {
            std::array<std::uint32_t, 3> local{};
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t v = mesh.triangles[t][k];
                auto [it, fresh] = remap.try_emplace(v, static_cast<std::uint32_t>(m.positions.size()));
                if (fresh) m.positions.push_back(mesh.positions[v]);
                local[k] = it->second;
            }
            m.triangles.push_back(local);
        }
        out.meshes.push_back(std::move(m));
    }
    for (std::size_t i = 0; i < out.meshes.size(); ++i)
        out.list.push_back(TileMesh{&out.meshes[i], out.meshes[i].bounds(), 1, nullptr, i});
    return out;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

TEST(TileCullingBunny, Stereo1280x720At256CellsWithAndWithoutCulling) {
    const char* assets = std::getenv("TRIDEX_ASSETS");
    const std::string path = (std::filesystem::path(assets ? assets : "assets") / "bunny.off").string();
    const TriMesh input = compute::load_closed_mesh(path);
    // The bunny 0.8 m across, centred 0.2 m in front of the PowerWall.
    const TriMesh world = compute::transformed(input, compute::fit_to_stock(input.bounds(), Vec3(0.0, 0.0, 0.2), 0.8));
    const compute::Lattice lattice = compute::Lattice::around(world.bounds(), 256);
    compute::TriDexel model = compute::TriDexel::empty(lattice, std::size_t(1) << 31);
    compute::scan_convert(world, model);
    compute::Contourer contourer(model);
    contourer.update(model);
    const TriMesh mesh = contourer.mesh();
    const Tiles tiles = split_into_tiles(mesh, lattice);
    std::printf("[bunny] 256 cells: %zu triangles in %zu non-empty tiles\n", mesh.triangles.size(), tiles.list.size());

    gpu::Context ctx = gpu::Context::create({});
    {
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, 1280, 720, EyeStrategy::kPassPerEye);
        SceneView v;
        v.show_workspace = false;
        v.tiles = tiles.list;
        v.show_overlay = true;
        v.frame_time_ms = 0.0;
        // Whole view: the wall from 2 m; close-up: head 0.45 m from the wall, off to the upper right.
        const Pose heads[2] = {Pose{Vec3(0.0, 0.0, 2.0)}, Pose{Vec3(0.35, 0.25, 0.45)}};
        const char* names[2] = {"whole", "close-up"};
        for (int h = 0; h < 2; ++h) {
            StereoImages images[2];
            for (int cull = 1; cull >= 0; --cull) {
                v.cull_tiles = cull == 1;
                std::vector<double> frame, opaque, translucent, overlay, wall;
                for (int i = 0; i < 5; ++i) {
                    const auto t0 = std::chrono::steady_clock::now();
                    images[cull] = r.render(v, Screen::powerwall(), heads[h], 0.065);
                    wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
                    const FrameStats& s = images[cull].stats;
                    frame.push_back(s.frame_ms);
                    opaque.push_back(s.pass_ms("opaque"));
                    translucent.push_back(s.pass_ms("translucent"));
                    overlay.push_back(s.pass_ms("overlay"));
                }
                const FrameStats& s = images[cull].stats;
                EXPECT_EQ(s.tiles[0].drawn + s.tiles[0].skipped, tiles.list.size());
                EXPECT_EQ(s.tiles[1].drawn + s.tiles[1].skipped, tiles.list.size());
                if (!v.cull_tiles) {
                    EXPECT_EQ(s.tiles[0].skipped + s.tiles[1].skipped, 0u);
                }
                std::printf("[bunny] %s view, culling %s, validation %s: tiles L %zu/%zu R %zu/%zu drawn/skipped; "
                            "median GPU frame %.1f ms (opaque %.1f, translucent %.2f, overlay %.2f, both eyes), "
                            "wall %.1f ms incl. readback\n",
                            names[h], cull ? "on " : "off", ctx.validation_enabled() ? "on" : "off", s.tiles[0].drawn,
                            s.tiles[0].skipped, s.tiles[1].drawn, s.tiles[1].skipped, median(frame), median(opaque),
                            median(translucent), median(overlay), median(wall));
            }
            // Culling never changes the image (the overlay text differs in the counts: compare below its panel,
            // 4 lines of 12 font units at scale 2 plus margins < 130 px).
            std::size_t differing = 0;
            for (int eye = 0; eye < 2; ++eye) {
                const Image& a = eye ? images[0].right : images[0].left;
                const Image& b = eye ? images[1].right : images[1].left;
                for (int y = 130; y < a.height; ++y)
                    for (int x = 0; x < a.width; ++x)
                        for (int c = 0; c < 4; ++c) differing += a.at(x, y)[c] != b.at(x, y)[c] ? 1 : 0;
            }
            EXPECT_EQ(differing, 0u) << names[h];
            if (h == 1) {
                EXPECT_GT(images[1].stats.tiles[0].skipped, 0u);
                write_png((std::filesystem::current_path() / "bunny_close_up.png").string(),
                          side_by_side(images[1].left, images[1].right));
            }
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
