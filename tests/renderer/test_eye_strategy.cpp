// Tests of the eye-strategy self-test on lavapipe and of the renderer's fallback to pass-per-eye.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/error.hpp"
#include "gpu/context.hpp"
#include "renderer/stereo/eye_self_test.hpp"
#include "renderer/stereo/eye_strategy.hpp"
#include "renderer/stereo/stereo_pipeline.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::renderer {
namespace {

constexpr EyeStrategy kAll[] = {EyeStrategy::kPassPerEye, EyeStrategy::kMultiview, EyeStrategy::kInstancedLayer};

TEST(EyeStrategy, Names) {
    EXPECT_EQ(to_string(EyeStrategy::kPassPerEye), "pass-per-eye");
    EXPECT_EQ(to_string(EyeStrategy::kMultiview), "multiview");
    EXPECT_EQ(to_string(EyeStrategy::kInstancedLayer), "instanced-layer");
}

// The expected self-test picture of both layers, or the picture of the lavapipe multiview failure:
// the right eye's clipped draws (bands 0 and 3) landing in layer 0 instead of layer 1.
Image self_test_picture(int layer, bool multiview_bug) {
    Image img = Image::filled(kSelfTestWidth, kSelfTestHeight, 0, 0, 0);
    for (int y = 0; y < kSelfTestHeight; ++y)
        for (int x = 0; x < kSelfTestWidth; ++x) {
            const bool clipped_band = y < 2 || y >= kSelfTestHeight - 2;
            const bool moved = multiview_bug && clipped_band && x >= kSelfTestWidth / 2;
            // moved pixels: taken from layer 1's expectation into layer 0, cleared in layer 1
            if (moved && layer == 1) continue;
            self_test_expected_pixel(moved ? 1 : layer, x, y, img.at(x, y));
        }
    return img;
}

TEST(EyeSelfTest, JudgeAcceptsCorrectLayersAndRejectsMisroutedDraws) {
    const EyeSelfTest good = judge_eye_layers(self_test_picture(0, false), self_test_picture(1, false));
    EXPECT_TRUE(good.passed) << good.detail;
    EXPECT_EQ(good.detail, "layer 0: 128/128 pixels as expected, layer 1: 128/128 pixels as expected");
    // 2 clipped bands x 2 rows x 8 pixels = 32 misplaced pixels in each layer.
    const EyeSelfTest bad = judge_eye_layers(self_test_picture(0, true), self_test_picture(1, true));
    EXPECT_FALSE(bad.passed);
    EXPECT_EQ(bad.detail, "layer 0: 96/128 pixels as expected, layer 1: 96/128 pixels as expected");
    // Both eyes in layer 1 swapped (a strategy that ignores the eye index entirely) also fails.
    const EyeSelfTest swapped = judge_eye_layers(self_test_picture(1, false), self_test_picture(0, false));
    EXPECT_FALSE(swapped.passed);
    EXPECT_THROW(judge_eye_layers(Image::filled(4, 4, 0, 0, 0), self_test_picture(1, false)), Error);
}

TEST(EyeStrategy, SelfTestReportsWhatTheDeviceDoes) {
    gpu::Context ctx = gpu::Context::create({});
    EXPECT_TRUE(supported(ctx, EyeStrategy::kPassPerEye));
    for (EyeStrategy s : kAll) {
        if (!supported(ctx, s)) {
            std::printf("[eye strategy] %-16s not supported by %s\n", to_string(s).data(), ctx.device_name().c_str());
            continue;
        }
        const StereoPipeline p = StereoPipeline::create(ctx, s);
        const EyeSelfTest t = self_test_eye_strategy(ctx, p);
        std::printf("[eye strategy] %-16s %s: %s\n", to_string(s).data(), t.passed ? "PASSED" : "FAILED",
                    t.detail.c_str());
        // One pass per eye needs nothing beyond core Vulkan 1.0 and must work everywhere.
        if (s == EyeStrategy::kPassPerEye) {
            EXPECT_TRUE(t.passed) << t.detail;
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(EyeStrategy, RendererUsesPreferredStrategyOnlyWhenItsSelfTestPasses) {
    gpu::Context ctx = gpu::Context::create({});
    for (EyeStrategy s : kAll) {
        bool passes = false;
        if (supported(ctx, s)) passes = self_test_eye_strategy(ctx, StereoPipeline::create(ctx, s)).passed;
        const OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, 32, 24, s);
        std::printf("[renderer] preferred %-16s -> %s: %s\n", to_string(s).data(), to_string(r.strategy()).data(),
                    r.strategy_note().c_str());
        EXPECT_EQ(r.strategy(), passes ? s : EyeStrategy::kPassPerEye) << r.strategy_note();
        if (!passes) {
            const bool explained = r.strategy_note().find("drew wrong pixels") != std::string::npos ||
                                   r.strategy_note().find("not supported") != std::string::npos;
            EXPECT_EQ(r.strategy_note().find("failed"), std::string::npos) << "reads as an error: " << r.strategy_note();
            EXPECT_TRUE(explained) << r.strategy_note();
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
