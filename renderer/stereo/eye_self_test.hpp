// renderer/stereo/eye_self_test.hpp - checks on the device that each eye's draws land in its own layer.
#pragma once

#include <string>

#include "gpu/context.hpp"
#include "renderer/image/image.hpp"
#include "renderer/stereo/stereo_pipeline.hpp"

namespace tridex::renderer {

/// Outcome of self_test_eye_strategy() / judge_eye_layers().
struct EyeSelfTest {
    bool passed = false;
    /// One line: per layer, how many pixels hold the expected value out of the total, e.g.
    /// "layer 0: 128/128 pixels as expected, layer 1: 64/128 pixels as expected".
    std::string detail;
};

/// Size of the self-test target, pixels. Rows are split into 4 bands of 2 rows, one per test draw.
constexpr int kSelfTestWidth = 16;
constexpr int kSelfTestHeight = 8;

/// The RGBA value the self-test expects at pixel (x, y) of `layer` (0 = left eye, 1 = right eye): draw
/// band = y / 2 coloured in the layer's own half (left half for layer 0, right half for layer 1), the
/// clear colour (0, 0, 0, 255) elsewhere. Writes 4 bytes to rgba.
void self_test_expected_pixel(int layer, int x, int y, std::uint8_t rgba[4]);

/// Compares read-back layers with self_test_expected_pixel(); passes only if every pixel matches exactly.
/// Throws tridex::Error if an image is not kSelfTestWidth x kSelfTestHeight.
EyeSelfTest judge_eye_layers(const Image& layer0, const Image& layer1);

/// Draws, with `pipeline`'s own pipelines, render pass and framebuffer layout, four flat-coloured unit
/// cubes into a kSelfTestWidth x kSelfTestHeight stereo target - one per row band, in the pipeline order
/// of a real frame (opaque, translucent back, translucent front, opaque again, each a different colour with
/// alpha 1) - the left eye's matrix squashing them onto the left half of the image and the right eye's onto
/// the right half; reads both layers back and judges them with judge_eye_layers(). The first and last
/// band extend past the image edges so their triangles are clipped: Mesa 22.3.6 lavapipe's multiview
/// routes unclipped triangles correctly but sends the clipped ones of view 1 into layer 0 (measured:
/// 96/128 pixels right per layer), which a test with only unclipped draws would miss.
/// Throws tridex::Error on a Vulkan failure.
EyeSelfTest self_test_eye_strategy(const gpu::Context& context, const StereoPipeline& pipeline);

}  // namespace tridex::renderer
