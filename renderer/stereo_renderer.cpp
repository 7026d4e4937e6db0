// renderer/stereo_renderer.cpp - scene -> draws -> stereo frame, with the eye-strategy fallback.
#include "renderer/stereo_renderer.hpp"

#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "core/error.hpp"
#include "gpu/check.hpp"
#include "renderer/eye_self_test.hpp"
#include "renderer/eyes_binding.hpp"
#include "renderer/gpu_mesh.hpp"
#include "renderer/primitive_meshes.hpp"
#include "renderer/stereo_frame.hpp"
#include "renderer/stereo_pipeline.hpp"
#include "renderer/stereo_target.hpp"

namespace tridex::renderer {
namespace {

// Scene colours (linear RGBA) and the light: from upper right, in front of the screen.
const glm::vec4 kWorkpieceColour(0.80f, 0.62f, 0.45f, 1.0f);
const glm::vec4 kToolColour(0.35f, 0.55f, 0.85f, 1.0f);
const glm::vec4 kWorkspaceColour(0.30f, 0.85f, 0.40f, 0.18f);
const glm::vec4 kBubbleColour(0.45f, 0.65f, 1.00f, 0.15f);
constexpr float kClear[4] = {0.08f, 0.09f, 0.11f, 1.0f};
const glm::vec3 kTowardsLight = glm::normalize(glm::vec3(0.35f, 0.6f, 1.0f));
constexpr int kSphereRings = 24, kSphereSegments = 48;

glm::mat4 translate_scale(const Vec3& t, const Vec3& s) {
    glm::mat4 m(1.0f);
    m[0][0] = static_cast<float>(s.x);
    m[1][1] = static_cast<float>(s.y);
    m[2][2] = static_cast<float>(s.z);
    m[3] = glm::vec4(glm::vec3(t), 1.0f);
    return m;
}

}  // namespace

struct OffscreenStereoRenderer::Impl {
    gpu::Context* context = nullptr;
    std::string note;
    std::optional<StereoPipeline> pipeline;
    std::optional<StereoTarget> target;
    std::optional<EyesBinding> eyes;
    GpuMesh workpiece, ball, cube;
    gpu::UniqueQueryPool timestamps;  // 2 queries: top and bottom of a frame (empty without timestamp support)
    std::uint64_t timestamp_mask = 0;  // timestampValidBits of the queue family as a mask
    std::uint64_t frames = 0;
    double gpu_ms = -1.0;

    ~Impl() {
        try {
            if (context) context->wait_idle();  // nothing should be pending: render() waits for its frame
        } catch (const Error& e) {
            std::fprintf(stderr, "renderer: %s\n", e.what());
        }
    }
};

OffscreenStereoRenderer OffscreenStereoRenderer::create(gpu::Context& context, int width, int height,
                                                        EyeStrategy preferred) {
    auto impl = std::make_unique<Impl>();
    impl->context = &context;
    const std::string asked(to_string(preferred));
    if (!supported(context, preferred)) {
        impl->note = asked + " not supported by " + context.device_name() + "; using pass-per-eye";
    } else {
        StereoPipeline p = StereoPipeline::create(context, preferred);
        const EyeSelfTest t = self_test_eye_strategy(context, p);
        if (t.passed) {
            impl->note = asked + " self-test passed (" + t.detail + ")";
            impl->pipeline.emplace(std::move(p));
        } else {
            impl->note = asked + " self-test failed (" + t.detail + "); falling back to pass-per-eye";
        }
    }
    if (!impl->pipeline) {
        StereoPipeline p = StereoPipeline::create(context, EyeStrategy::kPassPerEye);
        const EyeSelfTest t = self_test_eye_strategy(context, p);
        if (!t.passed)
            throw Error("renderer: even the pass-per-eye strategy failed its self-test on " + context.device_name() +
                        " (" + t.detail + ")");
        impl->note += " (pass-per-eye self-test passed)";
        impl->pipeline.emplace(std::move(p));
    }
    impl->target.emplace(StereoTarget::create(context, *impl->pipeline, width, height));
    impl->eyes.emplace(EyesBinding::create(context, impl->pipeline->set_layout()));
    TriMesh sphere = unit_sphere(kSphereRings, kSphereSegments);
    impl->ball.assign(context, sphere);
    Aabb unit;
    unit.add(Vec3(0.0));
    unit.add(Vec3(1.0));
    impl->cube.assign(context, box_mesh(unit));

    std::uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(context.physical_device(), &families, nullptr);
    std::vector<VkQueueFamilyProperties> family_props(families);
    vkGetPhysicalDeviceQueueFamilyProperties(context.physical_device(), &families, family_props.data());
    const std::uint32_t valid_bits = family_props.at(context.queue_family()).timestampValidBits;
    if (context.features().timestamps && valid_bits > 0) {
        impl->timestamp_mask = valid_bits >= 64 ? ~std::uint64_t{0} : ((std::uint64_t{1} << valid_bits) - 1);
        VkQueryPoolCreateInfo q{};
        q.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
        q.queryType = VK_QUERY_TYPE_TIMESTAMP;
        q.queryCount = 2;
        VkQueryPool pool = VK_NULL_HANDLE;
        gpu::check(vkCreateQueryPool(context.device(), &q, nullptr, &pool), "vkCreateQueryPool");
        impl->timestamps = gpu::UniqueQueryPool(context.device(), pool);
    }
    return OffscreenStereoRenderer(std::move(impl));
}

OffscreenStereoRenderer::OffscreenStereoRenderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
OffscreenStereoRenderer::~OffscreenStereoRenderer() = default;
OffscreenStereoRenderer::OffscreenStereoRenderer(OffscreenStereoRenderer&&) noexcept = default;
OffscreenStereoRenderer& OffscreenStereoRenderer::operator=(OffscreenStereoRenderer&&) noexcept = default;

EyeStrategy OffscreenStereoRenderer::strategy() const { return impl_->pipeline->strategy(); }
std::string OffscreenStereoRenderer::strategy_note() const { return impl_->note; }
int OffscreenStereoRenderer::width() const { return impl_->target->width(); }
int OffscreenStereoRenderer::height() const { return impl_->target->height(); }
VkImage OffscreenStereoRenderer::colour_image() const { return impl_->target->colour_image(); }
std::uint64_t OffscreenStereoRenderer::frames_rendered() const { return impl_->frames; }
double OffscreenStereoRenderer::last_gpu_ms() const { return impl_->gpu_ms; }

StereoImages OffscreenStereoRenderer::render(const SceneView& scene, const Screen& screen, const Pose& head,
                                             double eye_separation_m, double near_m, double far_m) {
    draw(scene, screen, head, eye_separation_m, near_m, far_m);
    return StereoImages{impl_->target->read_layer(0), impl_->target->read_layer(1)};
}

void OffscreenStereoRenderer::draw(const SceneView& scene, const Screen& screen, const Pose& head,
                                   double eye_separation_m, double near_m, double far_m) {
    Impl& im = *impl_;
    const std::array<Vec3, 2> eyes = eye_positions(head, eye_separation_m);
    EyesUniform u{};
    for (int e = 0; e < 2; ++e) {
        const EyeView v = off_axis_view(screen, eyes[e], near_m, far_m);
        u.clip_from_world[e] = glm::mat4(v.projection * v.view);
        u.eye_position[e] = glm::vec4(glm::vec3(eyes[e]), 1.0f);
    }
    u.light_direction = glm::vec4(kTowardsLight, 0.0f);

    std::vector<StereoDraw> draws;
    const auto add = [&](PipelineKind kind, const GpuMesh& mesh, const glm::mat4& model, const glm::vec4& colour,
                         bool lit) {
        StereoDraw d;
        d.kind = kind;
        d.vertices = mesh.vertices();
        d.indices = mesh.indices();
        d.index_count = mesh.index_count();
        d.constants.world_from_model = model;
        d.constants.colour = colour;
        d.constants.lit = lit ? 1u : 0u;
        draws.push_back(d);
    };
    if (scene.workpiece && !scene.workpiece->triangles.empty()) {
        im.workpiece.assign(*im.context, *scene.workpiece);
        add(PipelineKind::kOpaque, im.workpiece, glm::mat4(1.0f), kWorkpieceColour, true);
    }
    if (scene.tool_radius_m > 0.0) {
        if (!is_finite(scene.tool_centre_m) || !std::isfinite(scene.tool_radius_m))
            throw Error("renderer: SceneView.tool_centre_m / tool_radius_m must be finite");
        add(PipelineKind::kOpaque, im.ball, translate_scale(scene.tool_centre_m, Vec3(scene.tool_radius_m)),
            kToolColour, true);
    }
    if (scene.show_workspace && !scene.workspace_m.empty()) {
        if (!is_finite(scene.workspace_m.lo) || !is_finite(scene.workspace_m.hi))
            throw Error("renderer: SceneView.workspace_m must be finite");
        const glm::mat4 model = translate_scale(scene.workspace_m.lo, scene.workspace_m.size());
        add(PipelineKind::kTranslucentBack, im.cube, model, kWorkspaceColour, false);
        add(PipelineKind::kTranslucentFront, im.cube, model, kWorkspaceColour, false);
    }

    if (scene.bubble_radius_m > 0.0) {
        if (!is_finite(scene.bubble_centre_m) || !std::isfinite(scene.bubble_radius_m))
            throw Error("renderer: SceneView.bubble_centre_m / bubble_radius_m must be finite");
        const glm::mat4 model = translate_scale(scene.bubble_centre_m, Vec3(scene.bubble_radius_m));
        add(PipelineKind::kTranslucentBack, im.ball, model, kBubbleColour, false);
        add(PipelineKind::kTranslucentFront, im.ball, model, kBubbleColour, false);
    }

    im.eyes->write(u);
    const VkQueryPool pool = im.timestamps.get();
    im.context->submit_and_wait([&](VkCommandBuffer cmd) {
        if (pool != VK_NULL_HANDLE) {
            vkCmdResetQueryPool(cmd, pool, 0, 2);
            vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, pool, 0);
        }
        record_stereo_frame(cmd, *im.pipeline, *im.target, im.eyes->set(), draws, kClear);
        if (pool != VK_NULL_HANDLE) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool, 1);
    });
    ++im.frames;
    if (pool != VK_NULL_HANDLE) {
        std::uint64_t t[2] = {0, 0};
        const VkResult r = vkGetQueryPoolResults(im.context->device(), pool, 0, 2, sizeof t, t, sizeof t[0],
                                                 VK_QUERY_RESULT_64_BIT);
        if (r == VK_SUCCESS) {
            const std::uint64_t ticks = ((t[1] & im.timestamp_mask) - (t[0] & im.timestamp_mask)) & im.timestamp_mask;
            im.gpu_ms = static_cast<double>(ticks) * im.context->properties().limits.timestampPeriod * 1e-6;
        }
    }
}

}  // namespace tridex::renderer
