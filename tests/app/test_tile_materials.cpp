// Painted materials on the per-tile path: the same paint stroke, pushed as ToolSamples through a SculptThread that
// publishes MeshForm::kTiles and through one that publishes MeshForm::kWhole, is drawn offscreen from each hand-off
// as the renderer's tiles (TileMeshCache) and as the whole mesh. Both pictures show the painted spot in the palette
// colour of its material, alike to within rounding, and both differ there from the unpainted box.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "compute/mesh/scan_convert.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/primitives.hpp"
#include "gpu/context.hpp"
#include "renderer/camera/display_config.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/scene/material_palette.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {
namespace {

constexpr int kW = 320, kH = 240;
constexpr std::uint8_t kPaintMaterial = 2;

compute::TriDexel box_model() {
    const Aabb box{Vec3(-0.05), Vec3(0.05)};
    compute::TriDexel m = compute::TriDexel::empty(compute::Lattice::around(box, 32), std::size_t(1) << 30);
    compute::scan_convert(box_mesh(box), m);
    return m;
}

/// A paint stroke (material kPaintMaterial, 1.2 cm ball) across the +z face, crossing several tiles.
void push_paint(SpscRing<ToolSample>& ring) {
    for (int i = 0; i < 100; ++i) {
        ToolSample s;
        s.t_s = i * 1e-3;
        s.position = Vec3(-0.035 + 0.07 * i / 99.0, 0.01, 0.05);
        s.tool.radius_m = 0.012;
        s.op = ToolOp::kPaint;
        s.material = kPaintMaterial;
        ASSERT_TRUE(ring.try_push(s));
    }
}

/// Runs the stroke through a SculptThread publishing `form` (or no stroke) and returns the final hand-off.
MeshFrame sculpt(MeshForm form, bool paint) {
    compute::TriDexel m = box_model();
    compute::Contourer contourer(m);
    contourer.update(m);
    SpscRing<ToolSample> ring(1024);
    TripleBuffer<ActiveSurface> surface;
    TripleBuffer<MeshFrame> meshes;
    SculptThread t(m, contourer, ring, surface, Vec3(0.0));
    t.publish_mesh_to(meshes, 0.0, form);
    if (paint) push_paint(ring);
    t.start();
    t.stop();
    return meshes.latest();
}

/// The left eye of `frame` drawn the way the session draws it (tiles with their materials, or the whole mesh
/// with its materials), seen from 0.4 m in front of the box's +z face.
renderer::Image draw(renderer::OffscreenStereoRenderer& r, const MeshFrame& frame) {
    std::vector<renderer::TileMesh> tiles;
    for (const auto& tile : frame.tiles)
        tiles.push_back(renderer::TileMesh{&tile->mesh, tile->bounds_m, tile->version, &tile->materials, tile->id});
    renderer::SceneView v;
    v.show_workspace = false;
    if (frame.tiled) {
        v.tiles = tiles;
    } else {
        v.workpiece = &frame.mesh;
        v.workpiece_materials = &frame.materials;
    }
    const renderer::Screen screen{Vec3(-0.08, -0.06, 0.05), Vec3(0.08, -0.06, 0.05), Vec3(-0.08, 0.06, 0.05)};
    return r.render(v, screen, Pose{Vec3(0.0, 0.0, 0.45)}, renderer::kDefaultEyeSeparationM).left;
}

/// Pixels whose colour is closest to the painted material's palette hue rather than the clay's: the red-green
/// and blue-green differences of each pixel compared with those of the two palette colours.
std::size_t painted_pixels(const renderer::Image& img) {
    const auto& palette = renderer::material_palette();
    const glm::vec4 paint = palette[kPaintMaterial], clay = palette[0];
    std::size_t n = 0;
    for (std::size_t i = 0; i + 3 < img.rgba.size(); i += 4) {
        const float r = img.rgba[i], g = img.rgba[i + 1], b = img.rgba[i + 2];
        const float sum = r + g + b;
        if (sum < 30.0f) continue;  // background
        const auto distance = [&](const glm::vec4& c) {
            const float cs = c.r + c.g + c.b;
            const float dr = r / sum - c.r / cs, dg = g / sum - c.g / cs, db = b / sum - c.b / cs;
            return dr * dr + dg * dg + db * db;
        };
        if (distance(paint) < distance(clay)) ++n;
    }
    return n;
}

TEST(TileMaterials, TilePathShowsPaintLikeTheWholeMesh) {
    const MeshFrame tiled = sculpt(MeshForm::kTiles, true);
    const MeshFrame whole = sculpt(MeshForm::kWhole, true);
    const MeshFrame plain = sculpt(MeshForm::kTiles, false);
    ASSERT_TRUE(tiled.tiled);
    ASSERT_FALSE(whole.tiled);
    ASSERT_FALSE(tiled.tiles.empty());
    std::size_t painted_vertices = 0;
    for (const auto& tile : tiled.tiles) {
        ASSERT_EQ(tile->materials.size(), tile->mesh.positions.size()) << "tile " << tile->id;
        for (std::uint8_t id : tile->materials) painted_vertices += id == kPaintMaterial;
    }
    EXPECT_GT(painted_vertices, 50u);

    gpu::Context ctx = gpu::Context::create({});
    {
        renderer::OffscreenStereoRenderer r = renderer::OffscreenStereoRenderer::create(ctx, kW, kH);
        const renderer::Image tiled_img = draw(r, tiled);
        const renderer::Image whole_img = draw(r, whole);
        const renderer::Image plain_img = draw(r, plain);
        renderer::write_png("tile_materials_tiled.png", tiled_img);
        const std::size_t painted_tiled = painted_pixels(tiled_img), painted_whole = painted_pixels(whole_img);
        std::printf("painted pixels: tiles %zu, whole mesh %zu, unpainted box %zu\n", painted_tiled, painted_whole,
                    painted_pixels(plain_img));
        EXPECT_GT(painted_whole, 2000u);  // the stroke is about 7 x 2.4 cm seen at about 2000 px per m
        EXPECT_EQ(painted_pixels(plain_img), 0u);
        EXPECT_NEAR(static_cast<double>(painted_tiled), static_cast<double>(painted_whole), 0.01 * painted_whole);
        // Same surface, same colours: the tiles' picture is the whole mesh's up to rounding.
        const renderer::ImageComparison c = renderer::compare_images(tiled_img, whole_img, 3);
        std::printf("tiles vs whole: %zu of %zu pixels within 3, max channel difference %d\n", c.within, c.pixels,
                    c.max_channel_diff);
        EXPECT_GE(c.fraction_within(), 0.999);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::app
