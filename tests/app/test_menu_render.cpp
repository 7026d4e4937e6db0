// The open pie menu drawn offscreen in both eyes through the off-axis frusta: its slices sit at the hand's depth (the
// menu's disparity equals that of a marker at the hand, not zero as a flat overlay at the screen's plane would have),
// and a golden image of both eyes side by side.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "app/menu/pie_menu.hpp"
#include "app/menu/pie_menu_mesh.hpp"
#include "core/primitives.hpp"
#include "gpu/context.hpp"
#include "renderer/image/image.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/output/stereo_output.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {
namespace {

constexpr int kW = 240, kH = 180;
constexpr double kEyeSeparation = 0.065;
constexpr int kChannelTolerance = 3;          // as the renderer's goldens
constexpr double kMinFractionWithin = 0.995;  // of the pixels

// Mean x (pixel centres) of the pixels of `img` within 40 of colour `c` (linear 0..1 written as 8-bit sRGB codes are
// compared loosely: a channel-wise match of the dominant hue); count in n.
double mean_x_of(const renderer::Image& img, bool (*match)(const std::uint8_t*), std::size_t& n) {
    double sum = 0.0;
    n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (match(img.rgba.data() + (static_cast<std::size_t>(y) * img.width + x) * 4)) {
                sum += x + 0.5;
                ++n;
            }
    return n ? sum / static_cast<double>(n) : 0.0;
}

bool is_orange(const std::uint8_t* p) { return p[0] > 200 && p[1] > 90 && p[1] < 220 && p[2] < 90; }
bool is_green(const std::uint8_t* p) { return p[1] > 200 && p[0] < 80 && p[2] < 80; }

TEST(MenuRender, TheMenuSitsAtTheHandsDepthInBothEyesAndMatchesItsGolden) {
    const renderer::Screen screen{Vec3(-0.2, -0.15, 0.0), Vec3(0.2, -0.15, 0.0), Vec3(-0.2, 0.15, 0.0)};
    const Pose head{Vec3(0.0, 0.0, 0.6), Quat(1.0, 0.0, 0.0, 0.0)};
    const Vec3 hand(0.02, 0.0, 0.25);  // 0.25 m in front of the screen: a clear crossed disparity
    const MenuItem root = default_menu();
    PieMenu menu(PieMenuSettings{0.05, 0.012, 0.25});
    menu.open(root, hand, head.position, 0.0);
    // The hand at 3 o'clock of the ring, the slice there lit; a marker at the hand for its disparity.
    menu.update(hand + 0.03 * menu.ring().right, 0.5);
    ASSERT_TRUE(menu.shown(0.5));
    const std::vector<MenuPiece> pieces = pie_menu_pieces(menu.ring(), "operation: subtract");
    // The marker: a small green box at the hand, in the ring's hole (the ring's centre, the same depth as the slices).
    Aabb box;
    box.add(hand - Vec3(0.003));
    box.add(hand + Vec3(0.003));
    const TriMesh marker = box_mesh(box);
    // A wall of material between the head and the ring, as a workpiece in front of the hand would be: the menu is
    // drawn over it (on top), still at the hand's depth in each eye.
    Aabb wall;
    wall.add(Vec3(0.04, -0.01, 0.3));  // right of the marker at the hand, across the lit slice at 3 o'clock
    wall.add(Vec3(0.2, 0.01, 0.31));
    const TriMesh occluder = box_mesh(wall);
    std::vector<renderer::SceneObject> objects;
    objects.push_back({&occluder, glm::vec4(0.55f, 0.45f, 0.35f, 1.0f), 0b11, true});
    objects.push_back({&marker, glm::vec4(0.0f, 1.0f, 0.0f, 1.0f), 0b11, false});
    for (const MenuPiece& p : pieces) objects.push_back({&p.mesh, p.colour, 0b11, false, true});
    renderer::SceneView view;
    view.show_workspace = false;
    view.objects = objects;

    gpu::Context ctx = gpu::Context::create({});
    {
        renderer::OffscreenStereoRenderer r = renderer::OffscreenStereoRenderer::create(ctx, kW, kH);
        const renderer::StereoImages eyes = r.render(view, screen, head, kEyeSeparation);
        std::size_t nl = 0, nr = 0, ml = 0, mr = 0;
        // The lit slice's centre of mass is not the marker's, but both are at one depth: equal shifts between eyes. The
        // lit slice is whole in both eyes though the bar of material lies across the ring in front of it.
        const double lit_l = mean_x_of(eyes.left, is_orange, nl), lit_r = mean_x_of(eyes.right, is_orange, nr);
        const double mk_l = mean_x_of(eyes.left, is_green, ml), mk_r = mean_x_of(eyes.right, is_green, mr);
        ASSERT_GT(nl, 50u);
        ASSERT_GT(nr, 50u);
        ASSERT_GT(ml, 4u);
        ASSERT_GT(mr, 4u);
        const double menu_disparity = lit_l - lit_r, hand_disparity = mk_l - mk_r;
        // The off-axis prediction for a point 0.25 m in front of a 0.4 m wide screen seen from 0.6 m: e * d / (D - d)
        // metres on the screen, times kW / 0.4 pixels.
        const double predicted = kEyeSeparation * 0.25 / (0.6 - 0.25) * kW / 0.4;
        std::printf("[menu render] disparity of the lit slice %.2f px, of the marker at the hand %.2f px, predicted "
                    "%.2f px\n", menu_disparity, hand_disparity, predicted);
        EXPECT_GT(menu_disparity, 0.5 * predicted);  // crossed: in front of the screen, not at its plane
        EXPECT_NEAR(menu_disparity, hand_disparity, 1.0);
        EXPECT_NEAR(menu_disparity, predicted, 1.5);
        // Without the bar the lit slice shows the same pixels: the material in front hides none of it.
        std::vector<renderer::SceneObject> no_bar(objects.begin() + 1, objects.end());
        renderer::SceneView clear_view = view;
        clear_view.objects = no_bar;
        const renderer::StereoImages clear = r.render(clear_view, screen, head, kEyeSeparation);
        std::size_t cl = 0, cr = 0;
        (void)mean_x_of(clear.left, is_orange, cl);
        (void)mean_x_of(clear.right, is_orange, cr);
        EXPECT_EQ(nl, cl);
        EXPECT_EQ(nr, cr);
        // The golden image, both eyes side by side.
        const renderer::Image sbs = renderer::compose(renderer::StereoOutput::kSideBySide, eyes.left, eyes.right);
        const std::filesystem::path out = std::filesystem::current_path() / "menu_out";
        std::filesystem::create_directories(out);
        renderer::write_png((out / "menu_sbs_actual.png").string(), sbs);
        const char* data = std::getenv("TRIDEX_TEST_DATA");
        const std::filesystem::path golden =
            std::filesystem::path(data ? data : "tests/data") / "golden" / "outputs" / "pie_menu_sbs.png";
        ASSERT_TRUE(std::filesystem::exists(golden)) << "missing golden " << golden << "; candidate in " << out;
        const renderer::Image g = renderer::read_png(golden.string());
        ASSERT_EQ(g.width, sbs.width);
        ASSERT_EQ(g.height, sbs.height);
        const renderer::ImageComparison cmp = renderer::compare_images(sbs, g, kChannelTolerance);
        EXPECT_GE(cmp.fraction_within(), kMinFractionWithin) << "see " << out / "menu_sbs_actual.png";
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::app
