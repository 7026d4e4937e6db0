// Painted materials on screen: a contoured box whose face (in the screen plane, facing the viewer) has a
// spot painted with material 2 by the sweep's kPaint, drawn offscreen as the whole mesh with
// Contourer::mesh_materials() and as per-tile meshes with TileSurface::materials: pixels on the spot show
// the lit palette colour of material 2, pixels on the face away from it the clay colour (material 0).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/tools/sweep.hpp"
#include "compute/model/tridexel.hpp"
#include "gpu/context.hpp"
#include "renderer/scene/material_palette.hpp"
#include "renderer/camera/off_axis.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "test_scene.hpp"

namespace tridex::renderer {
namespace {

constexpr int kW = 400, kH = 300;  // over the 0.4 m x 0.3 m test screen: 1000 px per m
constexpr double kEyeSeparation = 0.065;
constexpr double kCell = 0.003125;  // m: the 32-cell box is 0.1 m across
const Vec3 kBoxLo(8.3, 8.3, 8.3), kBoxHi(39.6, 39.6, 31.6);  // grid units; the +z face lies in the screen plane
const Vec3 kSpotA(20.0, 24.0, 31.6), kSpotB(28.0, 24.0, 31.6);  // the paint stroke, grid units
constexpr double kSpotR = 8.0;                                  // cells

compute::Lattice box_lattice() {
    compute::Lattice l;
    l.cells = {48, 48, 48};
    l.cell_m = kCell;
    l.origin_m = Vec3(-24.0 * kCell, -24.0 * kCell, -31.6 * kCell);
    return l;
}

/// The box's chords on every ray, all tiles dirty.
compute::TriDexel box_model() {
    compute::TriDexel m = compute::TriDexel::empty(box_lattice(), std::size_t{1} << 30);
    for (int a = 0; a < 3; ++a) {
        compute::RaySet& s = m.sets[a];
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        for (int v = 0; v < s.nv; ++v)
            for (int u = 0; u < s.nu; ++u)
                if (u > kBoxLo[b] && u < kBoxHi[b] && v > kBoxLo[c] && v < kBoxHi[c])
                    s.ray(u, v) = {compute::Interval{static_cast<float>(kBoxLo[a]), static_cast<float>(kBoxHi[a])}};
    }
    std::fill(m.tiles.dirty.begin(), m.tiles.dirty.end(), std::uint8_t{1});
    return m;
}

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 d = b - a;
    const double t = std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0);
    return glm::length(p - (a + t * d));
}

struct Counts {
    int spot = 0, clay = 0, worst = 0;
};

/// Checks every pixel of both eyes whose centre (a point of the screen plane, where both eyes agree) lies on
/// the box face at least 3 cells inside its edges (nearer, vertex normals lean towards the side faces): within kSpotR - 2 cells of the stroke it must be material
/// 2's lit colour, beyond kSpotR + 3 cells clay's (each channel within 3 of 255).
Counts check(const StereoImages& e, const Pose& head, const compute::Lattice& l) {
    const auto eyes = eye_positions(head, kEyeSeparation);
    Counts n;
    for (int eye = 0; eye < 2; ++eye) {
        const Image& img = eye == 0 ? e.left : e.right;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const Vec3 p(-0.2 + (x + 0.5) / kW * 0.4, 0.15 - (y + 0.5) / kH * 0.3, 0.0);
                const Vec3 g = l.to_grid(p);
                if (g.x < kBoxLo.x + 3.0 || g.x > kBoxHi.x - 3.0 || g.y < kBoxLo.y + 3.0 || g.y > kBoxHi.y - 3.0) continue;
                const double d = distance_to_segment(Vec3(g.x, g.y, kSpotA.z), kSpotA, kSpotB);
                int material = -1;
                if (d <= kSpotR - 2.0) material = 2;
                if (d >= kSpotR + 3.0) material = 0;
                if (material < 0) continue;
                ++(material == 2 ? n.spot : n.clay);
                const auto want = test::lit_colour(material_palette()[static_cast<std::size_t>(material)], p, eyes[eye]);
                for (int c = 0; c < 3; ++c) {
                    const int diff = std::abs(img.at(x, y)[c] - want[c]);
                    if (diff > 3 && std::getenv("TRIDEX_DEBUG_MATERIALS"))
                        std::printf("eye %d px %d %d grid %.2f %.2f d %.2f mat %d got %d %d %d want %d %d %d\n", eye, x, y, g.x, g.y, d, material,
                                    img.at(x, y)[0], img.at(x, y)[1], img.at(x, y)[2], want[0], want[1], want[2]);
                    n.worst = std::max(n.worst, diff);
                }
            }
    }
    return n;
}

TEST(MaterialsContoured, PaintedSpotShowsItsPaletteColourWholeAndTiled) {
    compute::TriDexel model = box_model();
    compute::Contourer contourer(model);
    contourer.update(model);
    compute::Sweep paint;
    paint.op = ToolOp::kPaint;
    paint.tool = compute::SweepTool{compute::ToolKind::kBall, kSpotR * kCell, 0.0};
    paint.path_m = Segment{model.lattice.to_world(kSpotA), model.lattice.to_world(kSpotB)};
    paint.material = 2;
    ASSERT_GT(compute::apply_sweep(model, paint).rays_changed, 0u);
    contourer.update(model);
    const TriMesh mesh = contourer.mesh();
    const std::vector<std::uint8_t> materials = contourer.mesh_materials();
    compute::TileSurfaceCache cache;
    cache.refresh(contourer);
    std::vector<TileMesh> tiles;
    for (const compute::TileSurface& s : cache.tiles())
        tiles.push_back(TileMesh{&s.mesh, s.bounds_m, s.version, &s.materials, s.id});

    gpu::Context ctx = gpu::Context::create({});
    {
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH);
        const Pose head{Vec3(0.0, 0.0, 0.5)};
        SceneView v;
        v.show_workspace = false;
        v.tool_radius_m = 0.0;
        v.occlusion_strength = 0.0;  // the colours are checked against the lighting formula alone

        v.workpiece = &mesh;
        v.workpiece_materials = &materials;
        const StereoImages whole = r.render(v, test::small_screen(), head, kEyeSeparation);
        const Counts w = check(whole, head, model.lattice);
        std::printf("[whole] %d spot + %d clay pixels checked, worst channel difference %d\n", w.spot, w.clay, w.worst);
        EXPECT_GT(w.spot, 3000);  // both eyes; the checked part of the spot is about 12 x 20 cells of 3.1 px
        EXPECT_GT(w.clay, 2000);  // both eyes; the face's corners beyond kSpotR + 3 cells
        EXPECT_LE(w.worst, 3);

        v.workpiece = nullptr;
        v.workpiece_materials = nullptr;
        v.tiles = tiles;
        const StereoImages tiled = r.render(v, test::small_screen(), head, kEyeSeparation);
        const Counts t = check(tiled, head, model.lattice);
        std::printf("[tiles] %zu tiles, %d spot + %d clay pixels checked, worst channel difference %d\n",
                    tiles.size(), t.spot, t.clay, t.worst);
        EXPECT_EQ(t.spot, w.spot);
        EXPECT_EQ(t.clay, w.clay);
        EXPECT_LE(t.worst, 3);

        // Without the materials the tiles are all clay: the spot's pixels are not material 2's colour.
        for (TileMesh& tm : tiles) {
            tm.materials = nullptr;
            ++tm.version;  // make the cache re-upload the tile
        }
        v.tiles = tiles;
        const Counts plain = check(r.render(v, test::small_screen(), head, kEyeSeparation), head, model.lattice);
        EXPECT_GT(plain.worst, 40) << "the spot is visible without materials";
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
