// renderer/stereo/eye_self_test.cpp - the left-half / right-half layer routing test of an eye strategy.
#include "renderer/stereo/eye_self_test.hpp"

#include <string>

#include "core/error.hpp"
#include "renderer/stereo/eyes_binding.hpp"
#include "renderer/scene/gpu_mesh.hpp"
#include "renderer/scene/primitive_meshes.hpp"
#include "renderer/stereo/stereo_frame.hpp"
#include "renderer/stereo/stereo_target.hpp"

namespace tridex::renderer {
namespace {

constexpr int kBands = 4;
constexpr std::uint8_t kClear[4] = {0, 0, 0, 255};
// One colour per band / draw; channel values exactly representable after UNORM8 rounding.
constexpr std::uint8_t kBandColour[kBands][4] = {
    {255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {255, 255, 0, 255}};
constexpr PipelineKind kBandPipeline[kBands] = {PipelineKind::kOpaque, PipelineKind::kTranslucentBack,
                                                PipelineKind::kTranslucentFront, PipelineKind::kOpaque};

// Clip-from-world for eye `eye`: x in [0, 1] -> NDC [-1, 0] (left eye) or [0, 1] (right eye),
// y in [0, 1] -> NDC [-1, 1] (framebuffer rows top to bottom), constant depth 0.5, w = 1.
// No y flip, so exactly one face of the flattened cube is front-facing (-z) and one back-facing (+z):
// each pipeline (back-face or front-face culling) draws the cube exactly once.
glm::mat4 half_image_matrix(int eye) {
    glm::mat4 m(0.0f);  // column-major: m[column][row]
    m[0][0] = 1.0f;
    m[3][0] = eye == 0 ? -1.0f : 0.0f;
    m[1][1] = 2.0f;
    m[3][1] = -1.0f;
    m[3][2] = 0.5f;
    m[3][3] = 1.0f;
    return m;
}

}  // namespace

void self_test_expected_pixel(int layer, int x, int y, std::uint8_t rgba[4]) {
    const bool own_half = layer == 0 ? x < kSelfTestWidth / 2 : x >= kSelfTestWidth / 2;
    const std::uint8_t* c = own_half ? kBandColour[y * kBands / kSelfTestHeight] : kClear;
    for (int i = 0; i < 4; ++i) rgba[i] = c[i];
}

EyeSelfTest judge_eye_layers(const Image& layer0, const Image& layer1) {
    EyeSelfTest result;
    result.passed = true;
    const Image* layers[2] = {&layer0, &layer1};
    for (int layer = 0; layer < 2; ++layer) {
        const Image& img = *layers[layer];
        if (img.width != kSelfTestWidth || img.height != kSelfTestHeight ||
            img.rgba.size() != static_cast<std::size_t>(kSelfTestWidth) * kSelfTestHeight * 4)
            throw Error("judge_eye_layers: layer " + std::to_string(layer) + " is not " +
                        std::to_string(kSelfTestWidth) + "x" + std::to_string(kSelfTestHeight));
        int good = 0;
        for (int y = 0; y < kSelfTestHeight; ++y)
            for (int x = 0; x < kSelfTestWidth; ++x) {
                std::uint8_t want[4];
                self_test_expected_pixel(layer, x, y, want);
                const std::uint8_t* p = img.at(x, y);
                good += (p[0] == want[0] && p[1] == want[1] && p[2] == want[2] && p[3] == want[3]) ? 1 : 0;
            }
        if (good != kSelfTestWidth * kSelfTestHeight) result.passed = false;
        result.detail += (layer ? ", " : "") + std::string("layer ") + std::to_string(layer) + ": " +
                         std::to_string(good) + "/" + std::to_string(kSelfTestWidth * kSelfTestHeight) +
                         " pixels as expected";
    }
    return result;
}

EyeSelfTest self_test_eye_strategy(const gpu::Context& context, const StereoPipeline& pipeline) {
    const StereoTarget target = StereoTarget::create(context, pipeline, kSelfTestWidth, kSelfTestHeight);
    EyesBinding eyes = EyesBinding::create(context, pipeline.set_layout());
    EyesUniform u{};
    for (int e = 0; e < 2; ++e) {
        u.clip_from_world[e] = half_image_matrix(e);
        u.eye_position[e] = glm::vec4(0.5f, 0.5f, 2.0f, 1.0f);
    }
    u.light_direction = glm::vec4(0.0f, 0.0f, 1.0f, 0.0f);
    eyes.write(u);

    Aabb unit;
    unit.add(Vec3(0.0));
    unit.add(Vec3(1.0));
    GpuMesh cube;
    cube.assign(context, box_mesh(unit));

    StereoDraw draws[kBands];
    for (int i = 0; i < kBands; ++i) {
        draws[i].kind = kBandPipeline[i];
        draws[i].vertices = cube.vertices();
        draws[i].indices = cube.indices();
        draws[i].index_count = cube.index_count();
        // y in [0, 1] -> band [i, i + 1] / kBands; the first and last band reach 1 beyond the image's top
        // and bottom edges, so their triangles must be clipped (lavapipe's multiview mis-routes those).
        const float lo = i == 0 ? -1.0f : static_cast<float>(i) / kBands;
        const float hi = i == kBands - 1 ? 2.0f : static_cast<float>(i + 1) / kBands;
        glm::mat4 band(1.0f);
        band[1][1] = hi - lo;
        band[3][1] = lo;
        draws[i].constants.world_from_model = band;
        draws[i].constants.colour = glm::vec4(kBandColour[i][0], kBandColour[i][1], kBandColour[i][2], 255.0f) / 255.0f;
        draws[i].constants.lit = 0;
    }
    const float clear[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    context.submit_and_wait(
        [&](VkCommandBuffer cmd) { record_stereo_frame(cmd, pipeline, target, eyes.set(), draws, clear); });
    return judge_eye_layers(target.read_layer(0), target.read_layer(1));
}

}  // namespace tridex::renderer
