// renderer/stereo/stereo_renderer.cpp - scene -> draws -> stereo frame, with the eye-strategy fallback.
#include "renderer/stereo/stereo_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <utility>
#include <vector>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "core/error.hpp"
#include "gpu/check.hpp"
#include "renderer/scene/arrow_mesh.hpp"
#include "renderer/stereo/eye_self_test.hpp"
#include "renderer/stereo/eyes_binding.hpp"
#include "renderer/stereo/frame_draws.hpp"
#include "renderer/stereo/frame_eyes.hpp"
#include "renderer/stereo/frame_slots.hpp"
#include "renderer/scene/force_arrow.hpp"
#include "renderer/stereo/frame_timer.hpp"
#include "renderer/scene/gpu_mesh.hpp"
#include "renderer/scene/material_palette.hpp"
#include "renderer/scene/overlay_content.hpp"
#include "renderer/scene/overlay_text.hpp"
#include "renderer/scene/primitive_meshes.hpp"
#include "renderer/stereo/screen_region.hpp"
#include "renderer/stereo/stereo_frame.hpp"
#include "renderer/stereo/stereo_pipeline.hpp"
#include "renderer/stereo/stereo_target.hpp"
#include "renderer/scene/tile_culling.hpp"
#include "renderer/scene/tile_lod.hpp"
#include "renderer/stereo/draw_batching.hpp"
#include "renderer/stereo/tile_draws.hpp"

namespace tridex::renderer {
namespace {

// Scene colours (linear RGBA); the key light is frame_eyes' (renderer/stereo/frame_eyes.hpp).
const glm::vec4 kToolColour(0.35f, 0.55f, 0.85f, 1.0f);
const glm::vec4 kProxyColour(1.00f, 0.85f, 0.20f, 0.45f);
const glm::vec4 kForceColour(0.95f, 0.22f, 0.18f, 1.0f);
const glm::vec4 kWorkspaceColour(0.30f, 0.85f, 0.40f, 0.18f);
const glm::vec4 kBubbleColour(0.45f, 0.65f, 1.00f, 0.15f);
const glm::vec4 kOverlayPanelColour(0.0f, 0.0f, 0.0f, 0.55f);
const glm::vec4 kOverlayTextColour(0.95f, 0.95f, 0.80f, 1.0f);
constexpr float kClear[4] = {0.08f, 0.09f, 0.11f, 1.0f};
constexpr int kSphereRings = 24, kSphereSegments = 48, kArrowSegments = 16;
constexpr int kFramesInFlight = 2;

glm::mat4 translate_scale(const Vec3& t, const Vec3& s) {
    glm::mat4 m(1.0f);
    m[0][0] = static_cast<float>(s.x);
    m[1][1] = static_cast<float>(s.y);
    m[2][2] = static_cast<float>(s.z);
    m[3] = glm::vec4(glm::vec3(t), 1.0f);
    return m;
}

// Pixels (x right, y down) -> Vulkan clip space (x, y in -1..1, depth 0.5, w 1), the same for both eyes.
glm::mat4 clip_from_pixel(int width, int height) {
    glm::mat4 m(1.0f);
    m[0][0] = 2.0f / static_cast<float>(width);
    m[1][1] = 2.0f / static_cast<float>(height);
    m[2][2] = 0.0f;
    m[3] = glm::vec4(-1.0f, -1.0f, 0.5f, 1.0f);
    return m;
}

}  // namespace

// What one frame in flight owns: the uniforms and descriptor sets it reads, its timestamp queries, the meshes
// refilled every frame, and what is known of the frame drawn with it.
struct FrameResources {
    std::optional<EyesBinding> eyes;
    AmbientOcclusion occlusion;
    FrameTimer timer;
    GpuMesh workpiece, overlay_panel, overlay_text;
    DrawBatcher batcher;      // this frame's multi-draw commands
    FrameStats stats;         // counts at draw(); timings once the frame has finished
    bool gpu_timing = false;  // its timestamps were recorded
    bool timed = false;       // its timings are in `stats`
    bool occlusion_ran = false;  // it ran the ambient occlusion
    int eye_count = 2;
    std::chrono::steady_clock::time_point submitted{};
};

struct OffscreenStereoRenderer::Impl {
    gpu::Context* context = nullptr;
    std::string note;
    std::optional<StereoPipeline> pipeline;
    std::optional<StereoTarget> target;
    GpuMesh ball, cube, cylinder, cone;
    GpuMesh tool_mesh;                           // SceneView::tool_mesh, uploaded when it changes
    const TriMesh* tool_mesh_source = nullptr;
    std::size_t tool_mesh_triangles = 0;
    struct ObjectMesh {                           // SceneView::objects[i], uploaded when it changes
        GpuMesh mesh;
        const TriMesh* source = nullptr;
        std::size_t triangles = 0;
    };
    std::vector<ObjectMesh> objects;
    TileMeshCache tiles;
    TileMeshCache groups{"SceneView.tile_groups"};  // SceneView::tile_groups' levels
    std::vector<FrameResources> frame;  // one per slot
    FrameSlots slots;                   // after `tiles` and `frame`: destroyed (waiting for the GPU) before them
    bool use_timestamps = true;
    std::uint64_t frames = 0;
    std::uint64_t last_frame = 0;       // FrameSlots number of the last frame drawn
    int last_slot = 0;
    double gpu_ms = -1.0;               // GPU time of the latest finished frame
    FrameStats last;
    FrameStats finished;                // timings of the latest finished frame
    std::vector<FrameStats> finished_queue;  // take_finished_frames()
    int last_eye_count = 2;
    std::vector<PixelRect> last_drawn;  // the last submitted frame's drawn rectangles, both eyes
    bool last_read_back = false;  // the last frame's colour layers are in the target's readback buffer
    bool target_empty = false;    // resize() made a new target that no frame has been drawn into yet
    std::uint64_t target_generation = 0;  // targets resize() made

    // After frame `slot` has finished: its timings (GPU timestamps, or the CPU clock from submission to now).
    void time_finished(int slot) {
        FrameResources& f = frame[static_cast<std::size_t>(slot)];
        if (f.timed || slots.frame_of(slot) == 0) return;
        f.timed = true;
        FrameStats& stats = f.stats;
        if (f.gpu_timing && f.timer.read(*context, stats)) {
            if (f.eye_count == 1)  // the right eye's render pass was not recorded (its boundaries are zero-length)
                std::erase_if(stats.passes, [](const PassTime& p) { return p.eye == 1; });
            if (!f.occlusion_ran)  // nothing ran between its boundaries: no time to report for it
                std::erase_if(stats.passes, [](const PassTime& p) { return p.pass == "occlusion"; });
            gpu_ms = stats.frame_ms;
        } else {
            const double cpu_ms =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - f.submitted).count();
            stats.timing = TimingSource::kCpuClock;
            stats.timing_note = !f.timer.available()
                                    ? "no timestamp queries on this queue family; CPU clock from submit to finish seen"
                                : !f.gpu_timing ? "GPU timestamps switched off; CPU clock from submit to finish seen"
                                                : "timestamp results not available; CPU clock from submit to finish seen";
            stats.frame_ms = cpu_ms;
            stats.passes = {PassTime{"frame", -1, cpu_ms}};
            gpu_ms = -1.0;
        }
        finished = stats;
        finished_queue.push_back(stats);
        if (slot == last_slot && slots.frame_of(slot) == last_frame) last = stats;
    }
    // The steps of draw(), each appending its items to `list` (stereo_renderer.cpp): the whole-mesh workpiece, the
    // workpiece tiles and groups (synced to the scene's, counts and uploads in `stats`), the tool, the scene objects
    // (opaque ones drawn, the translucent ones' indices returned), the translucent items, the overlay; each throws
    // tridex::Error on the SceneView field it checks. submit() records and submits the frame in `slot` and returns its
    // statistics (the latest finished frame's timings until it finishes).
    void add_workpiece(const SceneView& scene, FrameResources& fr, FrameDraws& list);
    void add_tiles(const SceneView& scene, const FrameEyes& eyes, FrameDraws& list, FrameStats& stats);
    void add_tool(const SceneView& scene, FrameDraws& list);
    std::vector<std::size_t> add_objects(const SceneView& scene, FrameDraws& list);
    void add_translucent_items(const SceneView& scene, std::span<const std::size_t> translucent_objects, FrameDraws& list);
    void add_overlay(const SceneView& scene, const FrameStats& stats, FrameResources& fr, FrameDraws& list);
    FrameStats submit(const SceneView& scene, int slot, const EyesUniform& uniform, FrameDraws& list, FrameStats stats);

    // Waits for the last frame drawn and takes the timings of every frame in flight, oldest first.
    void finish_last() {
        if (last_frame == 0) return;
        slots.wait(last_frame);
        std::vector<int> order(frame.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
        std::sort(order.begin(), order.end(), [&](int a, int b) { return slots.frame_of(a) < slots.frame_of(b); });
        for (int slot : order) time_finished(slot);
    }

    ~Impl() {
        try {
            if (context) context->wait_idle();
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
        impl->note = "eyes drawn pass per eye: " + asked + " is not supported by " + context.device_name();
    } else {
        StereoPipeline p = StereoPipeline::create(context, preferred);
        const EyeSelfTest t = self_test_eye_strategy(context, p);
        if (t.passed) {
            impl->note = asked + " self-test passed (" + t.detail + ")";
            impl->pipeline.emplace(std::move(p));
        } else {
            impl->note = "eyes drawn pass per eye: " + asked + " (both eyes in one pass) drew wrong pixels in its start-up "
                         "check on this device (" + t.detail + "), so it is not used; the picture is not affected";
        }
    }
    if (!impl->pipeline) {
        StereoPipeline p = StereoPipeline::create(context, EyeStrategy::kPassPerEye);
        const EyeSelfTest t = self_test_eye_strategy(context, p);
        if (!t.passed)
            throw Error("renderer: even the pass-per-eye strategy failed its self-test on " + context.device_name() +
                        " (" + t.detail + ")");
        impl->note += " (the pass-per-eye check passed)";
        impl->pipeline.emplace(std::move(p));
    }
    impl->target.emplace(StereoTarget::create(context, *impl->pipeline, width, height));
    impl->slots = FrameSlots::create(context, kFramesInFlight);
    impl->frame.resize(kFramesInFlight);
    for (FrameResources& f : impl->frame) {
        f.eyes.emplace(EyesBinding::create(context, impl->pipeline->set_layout()));
        f.occlusion = AmbientOcclusion::create(context, *impl->target, f.eyes->buffer());
        f.timer = FrameTimer::create(context, impl->pipeline->strategy());
    }
    impl->ball.assign(context, unit_sphere(kSphereRings, kSphereSegments));
    Aabb unit;
    unit.add(Vec3(0.0));
    unit.add(Vec3(1.0));
    impl->cube.assign(context, box_mesh(unit));
    impl->cylinder.assign(context, unit_cylinder(kArrowSegments));
    impl->cone.assign(context, unit_cone(kArrowSegments));
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

void OffscreenStereoRenderer::resize(int width, int height) {
    Impl& im = *impl_;
    if (width == im.target->width() && height == im.target->height()) return;
    im.context->wait_idle();  // no frame in flight, and no blit of the old colour image pending, reads the old target
    StereoTarget next = StereoTarget::create(*im.context, *im.pipeline, width, height);
    im.target.reset();  // the occlusion images below are made for the new target
    im.target.emplace(std::move(next));
    for (FrameResources& f : im.frame) f.occlusion.retarget(*im.context, *im.target);
    im.last_read_back = false;
    im.target_empty = true;
    ++im.target_generation;
}
std::uint64_t OffscreenStereoRenderer::target_generation() const { return impl_->target_generation; }
VkImage OffscreenStereoRenderer::colour_image() const { return impl_->target->colour_image(); }
VkImageView OffscreenStereoRenderer::colour_array_view() const { return impl_->target->colour_array_view(); }
std::uint64_t OffscreenStereoRenderer::frames_rendered() const { return impl_->frames; }
double OffscreenStereoRenderer::last_gpu_ms() const { return impl_->gpu_ms; }
const FrameStats& OffscreenStereoRenderer::last_frame_stats() const { return impl_->last; }
const std::vector<PixelRect>& OffscreenStereoRenderer::last_drawn_rects() const { return impl_->last_drawn; }
std::array<std::uint8_t, 3> OffscreenStereoRenderer::clear_codes() {
    // UNORM8 stores round(value x 255) (Vulkan's float to normalized fixed-point conversion).
    std::array<std::uint8_t, 3> c{};
    for (int i = 0; i < 3; ++i) c[i] = static_cast<std::uint8_t>(std::lround(kClear[i] * 255.0f));
    return c;
}
bool OffscreenStereoRenderer::gpu_timestamps_available() const { return impl_->frame.front().timer.available(); }
void OffscreenStereoRenderer::set_gpu_timestamps(bool use) { impl_->use_timestamps = use; }
std::uint64_t OffscreenStereoRenderer::tile_uploads_total() const { return impl_->tiles.uploads_total(); }
std::size_t OffscreenStereoRenderer::tile_buffers() const { return impl_->tiles.buffers(); }
std::size_t OffscreenStereoRenderer::tile_memory_blocks() const { return impl_->tiles.memory_blocks(); }

StereoImages OffscreenStereoRenderer::render(const SceneView& scene, const Screen& screen, const Pose& head,
                                             double eye_separation_m, double near_m, double far_m) {
    draw(scene, screen, head, eye_separation_m, near_m, far_m);
    impl_->finish_last();
    return last_images();
}

std::vector<FrameStats> OffscreenStereoRenderer::take_finished_frames() {
    return std::exchange(impl_->finished_queue, {});
}

FrameStats OffscreenStereoRenderer::finish() {
    impl_->finish_last();
    return impl_->last;
}

StereoImages OffscreenStereoRenderer::last_images() const {
    Impl& im = *impl_;
    if (im.frames == 0 || im.target_empty) throw Error("renderer: last_images() before the first frame (since resize())");
    im.finish_last();
    if (!im.last_read_back) {  // frames are not copied back unless asked: a window presents by blits
        im.context->submit_and_wait(
            [&](VkCommandBuffer cmd) { record_readback(cmd, *im.target, im.last_eye_count); });
        im.last_read_back = true;
    }
    Image left = im.target->read_layer(0);
    Image right = im.last_eye_count == 1 ? left : im.target->read_layer(1);
    return StereoImages{std::move(left), std::move(right), im.last};
}

namespace {

// Throws tridex::Error for a SceneView whose eye count or ambient-occlusion settings are out of range.
void check_scene_view(const SceneView& scene) {
    if (scene.eye_count != 1 && scene.eye_count != 2)
        throw Error("renderer: SceneView.eye_count must be 1 (mono) or 2 (stereo), got " +
                    std::to_string(scene.eye_count));
    if (!std::isfinite(scene.occlusion_radius_m) || !std::isfinite(scene.occlusion_strength) ||
        scene.occlusion_radius_m < 0.0 || scene.occlusion_strength < 0.0)
        throw Error("renderer: SceneView.occlusion_radius_m and occlusion_strength must be finite and >= 0");
}

// The force arrow from the tool centre (SceneView::force_N times force_m_per_newton), when visible.
void add_force_arrow(const SceneView& scene, const GpuMesh& cylinder, const GpuMesh& cone, FrameDraws& list) {
    const ForceArrowTransforms arrow = force_arrow(scene.tool_centre_m, scene.force_N, scene.force_m_per_newton);
    if (!arrow.visible) return;
    // From the tool centre to the tip, widened by more than the head's radius.
    const Vec3 tip = scene.tool_centre_m + scene.force_N * scene.force_m_per_newton;
    Aabb box{glm::min(scene.tool_centre_m, tip), glm::max(scene.tool_centre_m, tip)};
    box.lo -= Vec3(0.02);
    box.hi += Vec3(0.02);
    list.cover(0b11u, box);
    list.add(PipelineKind::kOpaque, cylinder, glm::mat4(arrow.shaft), kForceColour, true);
    list.add(PipelineKind::kOpaque, cone, glm::mat4(arrow.head), kForceColour, true);
}

}  // namespace

void OffscreenStereoRenderer::Impl::add_workpiece(const SceneView& scene, FrameResources& fr, FrameDraws& list) {
    if (!scene.workpiece || scene.workpiece->triangles.empty()) return;
    std::span<const std::uint8_t> materials;
    if (scene.workpiece_materials) materials = *scene.workpiece_materials;
    try {
        fr.workpiece.assign(*context, *scene.workpiece, materials);
    } catch (const Error& e) {
        throw Error(std::string("SceneView.workpiece: ") + e.what());
    }
    list.cover_all();
    // Without materials the flat clay colour (palette[0]) keeps the images bit-identical to earlier ones.
    list.add(PipelineKind::kOpaque, fr.workpiece, glm::mat4(scene.workpiece_pose.matrix()), palette_colours(scene.palette)[0], true).constants.palette =
        scene.workpiece_materials ? 1u : 0u;
}

void OffscreenStereoRenderer::Impl::add_tiles(const SceneView& scene, const FrameEyes& eyes, FrameDraws& list,
                                              FrameStats& stats) {
    // Groups alone (a coarse-first start-up's first frames) are drawn too.
    if (scene.tiles.empty() && tiles.size() == 0 && scene.tile_groups.empty() && groups.size() == 0) return;
    // Tiles read back from the GPU contour: stored and drawn in its grid units.
    ModelFrame frame;
    glm::mat4 world_from_model(scene.workpiece_pose.matrix());
    if (scene.tiles_from_indirect) {
        if (!scene.indirect_workpiece) throw Error("renderer: SceneView.tiles_from_indirect needs indirect_workpiece");
        frame = ModelFrame{scene.indirect_workpiece->grid_origin_m, scene.indirect_workpiece->cell_m};
        world_from_model = world_from_model * scene.indirect_workpiece->world_from_grid;
    }
    std::vector<GpuMesh> retired;  // replaced tiles' buffers: earlier frames in flight may still read them
    tiles.sync(*context, scene.tiles, &retired, frame);
    for (GpuMesh& m : retired) slots.retire(std::move(m));
    retired.clear();
    if (!scene.tile_groups.empty() || groups.size() > 0) {
        std::vector<TileMesh> group_meshes(scene.tile_groups.size());
        for (std::size_t g = 0; g < scene.tile_groups.size(); ++g) {
            const TileGroup& tg = scene.tile_groups[g];
            group_meshes[g].bounds_m = tg.bounds_m;
            group_meshes[g].version = tg.version;
            group_meshes[g].id = tg.id;
            group_meshes[g].levels = tg.levels;
        }
        try {
            groups.sync(*context, group_meshes, &retired, frame);
        } catch (const Error& e) {
            throw Error(std::string("SceneView.tile_groups: ") + e.what());
        }
        for (GpuMesh& m : retired) slots.retire(std::move(m));
    }
    TileDrawEyes te;
    te.strategy = pipeline->strategy();
    te.eye_count = scene.eye_count;
    te.frusta = eyes.frusta;
    te.lod_eyes = eyes.lod;
    const glm::vec4 clay = palette_colours(scene.palette)[0];
    // The tiles' bounds are in the workpiece's model frame: the eyes go there, the covered boxes come back.
    add_tile_draws(
        scene, in_model_frame(te, scene.workpiece_pose), tiles, groups,
        [&](const GpuMesh& m) -> StereoDraw& {
            return list.add(PipelineKind::kOpaque, m, world_from_model, clay, true);
        },
        [&](std::uint32_t mask, const Aabb& box_m) { list.cover(mask, placed(box_m, scene.workpiece_pose)); }, stats);
    stats.tile_uploads = tiles.take_uploads() + groups.take_uploads();
}

void OffscreenStereoRenderer::Impl::add_tool(const SceneView& scene, FrameDraws& list) {
    if (!(scene.tool_radius_m > 0.0)) return;
    if (!is_finite(scene.tool_centre_m) || !std::isfinite(scene.tool_radius_m))
        throw Error("renderer: SceneView.tool_centre_m / tool_radius_m must be finite");
    const ToolShape& ts = scene.tool_shape;
    const auto cover_ball = [&](const Vec3& c, double r) { list.cover(0b11u, Aabb{c - Vec3(r), c + Vec3(r)}); };
    if (ts.kind == ToolKind::kFlatEnd && ts.radius_m > 0.0 && ts.length_m > 0.0) {
        cover_ball(scene.tool_centre_m, ts.radius_m + ts.length_m);
        // unit_cylinder runs along +z from 0 to 1; the tool's shank runs along its frame's +y.
        const glm::dmat4 m = glm::translate(glm::dmat4(1.0), scene.tool_centre_m) * glm::mat4_cast(scene.tool_orientation) *
                             glm::rotate(glm::dmat4(1.0), -0.5 * glm::pi<double>(), Vec3(1.0, 0.0, 0.0)) *
                             glm::scale(glm::dmat4(1.0), Vec3(ts.radius_m, ts.radius_m, ts.length_m));
        list.add(PipelineKind::kOpaque, cylinder, glm::mat4(m), kToolColour, true);
    } else if (ts.kind == ToolKind::kMesh && scene.tool_mesh && !scene.tool_mesh->triangles.empty()) {
        list.cover_all();
        if (scene.tool_mesh != tool_mesh_source || scene.tool_mesh->triangles.size() != tool_mesh_triangles) {
            slots.retire(std::move(tool_mesh));  // earlier frames in flight may still read it
            tool_mesh = GpuMesh{};
            tool_mesh.assign(*context, *scene.tool_mesh);
            tool_mesh_source = scene.tool_mesh;
            tool_mesh_triangles = scene.tool_mesh->triangles.size();
        }
        const glm::dmat4 m = glm::translate(glm::dmat4(1.0), scene.tool_centre_m) * glm::mat4_cast(scene.tool_orientation);
        list.add(PipelineKind::kOpaque, tool_mesh, glm::mat4(m), kToolColour, true);
    } else {
        cover_ball(scene.tool_centre_m, scene.tool_radius_m);
        list.add(PipelineKind::kOpaque, ball, translate_scale(scene.tool_centre_m, Vec3(scene.tool_radius_m)), kToolColour,
                 true);
    }
}

std::vector<std::size_t> OffscreenStereoRenderer::Impl::add_objects(const SceneView& scene, FrameDraws& list) {
    if (objects.size() < scene.objects.size()) objects.resize(scene.objects.size());
    std::vector<std::size_t> later;  // translucent objects (drawn with the translucent items), then on-top ones
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const SceneObject& o = scene.objects[i];
        if (!o.mesh || o.mesh->triangles.empty()) continue;
        for (int c = 0; c < 4; ++c)
            if (!(o.colour[c] >= 0.0f && o.colour[c] <= 1.0f))
                throw Error("renderer: SceneView.objects[" + std::to_string(i) + "].colour must be in [0, 1]");
        ObjectMesh& om = objects[i];
        if (o.mesh != om.source || o.mesh->triangles.size() != om.triangles) {
            if (om.source) {  // earlier frames in flight may still read the buffers it had
                slots.retire(std::move(om.mesh));
                om.mesh = GpuMesh{};
            }
            try {
                om.mesh.assign(*context, *o.mesh);
            } catch (const Error& e) {
                throw Error("SceneView.objects[" + std::to_string(i) + "]: " + e.what());
            }
            om.source = o.mesh;
            om.triangles = o.mesh->triangles.size();
        }
        if (o.colour.a < 1.0f || o.on_top)
            later.push_back(i);
        else {
            list.cover_all();
            list.add(PipelineKind::kOpaque, om.mesh, o.world_from_model, o.colour, o.lit).eye_mask = o.eyes & 0b11u;
        }
    }
    return later;
}

void OffscreenStereoRenderer::Impl::add_translucent_items(const SceneView& scene, std::span<const std::size_t> translucent_objects,
                                                          FrameDraws& list) {
    const auto ball_box = [](const Vec3& c, double r) { return Aabb{c - Vec3(r), c + Vec3(r)}; };
    for (const std::size_t i : translucent_objects) {
        if (scene.objects[i].on_top) continue;
        list.cover_drawn_all();
        list.add_translucent(objects[i].mesh, scene.objects[i].world_from_model, scene.objects[i].colour,
                             scene.objects[i].lit);
        std::vector<StereoDraw>& d = list.draws();  // its back and front faces
        d[d.size() - 1].eye_mask = d[d.size() - 2].eye_mask = scene.objects[i].eyes & 0b11u;
    }
    if (scene.proxy_radius_m > 0.0) {
        if (!is_finite(scene.proxy_m) || !std::isfinite(scene.proxy_radius_m))
            throw Error("renderer: SceneView.proxy_m / proxy_radius_m must be finite");
        list.cover_drawn(0b11u, ball_box(scene.proxy_m, scene.proxy_radius_m));
        list.add_translucent(ball, translate_scale(scene.proxy_m, Vec3(scene.proxy_radius_m)), kProxyColour, true);
    }
    if (scene.show_workspace && !scene.workspace_m.empty()) {
        if (!is_finite(scene.workspace_m.lo) || !is_finite(scene.workspace_m.hi))
            throw Error("renderer: SceneView.workspace_m must be finite");
        list.cover_drawn(0b11u, scene.workspace_m);
        list.add_translucent(cube, translate_scale(scene.workspace_m.lo, scene.workspace_m.size()), kWorkspaceColour, false);
    }
    if (scene.bubble_radius_m > 0.0) {
        if (!is_finite(scene.bubble_centre_m) || !std::isfinite(scene.bubble_radius_m))
            throw Error("renderer: SceneView.bubble_centre_m / bubble_radius_m must be finite");
        list.cover_drawn(0b11u, ball_box(scene.bubble_centre_m, scene.bubble_radius_m));
        list.add_translucent(ball, translate_scale(scene.bubble_centre_m, Vec3(scene.bubble_radius_m)), kBubbleColour, false);
    }
}

void OffscreenStereoRenderer::Impl::add_overlay(const SceneView& scene, const FrameStats& stats, FrameResources& fr,
                                                FrameDraws& list) {
    if (!scene.show_overlay) return;
    const int width = target->width(), height = target->height();
    OverlayNumbers n;
    n.haptic_rate_hz = scene.haptic_rate_hz;
    n.sculpt_rate_hz = scene.sculpt_rate_hz;
    n.frame_ms = scene.frame_time_ms >= 0.0 ? scene.frame_time_ms : last.frame_ms;
    n.has_tiles = scene.overlay_tile_counts &&
                  (!scene.tiles.empty() || (scene.indirect_workpiece && !scene.indirect_workpiece->tiles.empty()));
    n.tiles = stats.tiles;
    n.status = scene.overlay_status;
    const std::string text = overlay_content(n);
    const double scale = scene.overlay_scale > 0.0 ? scene.overlay_scale : overlay_scale_for(height, height);
    const TextExtent size = overlay_text_extent(text, scale);
    const double margin = 6.0 * scale, pad = 3.0 * scale;
    fr.overlay_panel.assign(*context, overlay_rectangle(margin - pad, margin - pad, margin + size.width_px + pad,
                                                        margin + size.height_px + pad));
    fr.overlay_text.assign(*context, overlay_text_mesh(text, margin, margin, scale));
    const glm::mat4 to_clip = clip_from_pixel(width, height);
    list.cover_drawn(PixelRect{static_cast<int>(std::floor(margin - pad)) - 1,
                               static_cast<int>(std::floor(margin - pad)) - 1,
                               static_cast<int>(std::ceil(margin + size.width_px + pad)) + 1,
                               static_cast<int>(std::ceil(margin + size.height_px + pad)) + 1});
    list.add(PipelineKind::kOverlay, fr.overlay_panel, to_clip, kOverlayPanelColour, false).constants.screen_space = 1;
    list.add(PipelineKind::kOverlay, fr.overlay_text, to_clip, kOverlayTextColour, false).constants.screen_space = 1;
}

FrameStats OffscreenStereoRenderer::Impl::submit(const SceneView& scene, int slot, const EyesUniform& uniform,
                                                 FrameDraws& list, FrameStats stats) {
    FrameResources& fr = frame[static_cast<std::size_t>(slot)];
    const int eye_count = scene.eye_count;
    const bool occlusion = scene.occlusion_radius_m > 0.0 && scene.occlusion_strength > 0.0;
    std::vector<StereoDraw>& draws = list.draws();
    fr.eyes->write(uniform);
    last_drawn = list.drawn_rects(eye_count == 1 ? 0b01u : 0b11u);
    fr.gpu_timing = use_timestamps && fr.timer.available();
    const VkCommandBuffer cmd = slots.command_buffer(slot);
    stats.draws_merged = fr.batcher.batch(*context, pipeline->strategy(), eye_count, draws);
    stats.draws = draws.size();
    if (fr.gpu_timing) fr.timer.record_begin(cmd);
    record_stereo_frame(cmd, *pipeline, *target, fr.eyes->set(), draws, kClear,
                        fr.gpu_timing ? fr.timer.phases() : PhaseTimestamps{}, eye_count,
                        occlusion ? &fr.occlusion : nullptr, list.opaque_region(), false, scene.occlusion_resolution);
    last_read_back = false;
    if (fr.gpu_timing) fr.timer.record_end(cmd);
    fr.submitted = std::chrono::steady_clock::now();
    stats.frame = frames + 1;
    fr.stats = stats;
    fr.timed = false;
    fr.occlusion_ran = occlusion;
    fr.eye_count = eye_count;
    last_frame = slots.submit(slot);
    last_slot = slot;
    ++frames;
    target_empty = false;
    // Until this frame finishes, its statistics carry the timings of the latest finished one.
    stats.timing = finished.timing;
    stats.timing_note = finished.timing_note;
    stats.frame_ms = finished.frame_ms;
    stats.passes = finished.passes;
    if (scene.indirect_workpiece) {  // its buffers may change once draw() returns: finish the frame now
        last = stats;
        last_eye_count = eye_count;
        finish_last();
        return last;
    }
    last = stats;
    last_eye_count = eye_count;
    return stats;
}

FrameStats OffscreenStereoRenderer::draw(const SceneView& scene, const Screen& screen, const Pose& head,
                                         double eye_separation_m, double near_m, double far_m) {
    Impl& im = *impl_;
    check_scene_view(scene);
    const FrameEyes eyes = frame_eyes(scene, screen, head, eye_separation_m, near_m, far_m, width(), height());
    // This frame's slot: waits only for the frame that used it kFramesInFlight frames ago.
    const int slot = im.slots.begin();
    im.time_finished(slot);
    FrameResources& fr = im.frame[static_cast<std::size_t>(slot)];
    FrameStats stats;
    FrameDraws list(eyes.clip_from_world, width(), height());
    // Opaque: workpiece (whole mesh), workpiece tiles (culled per eye), tool, force arrow; then the scene objects:
    // opaque ones now, translucent ones first among the translucent items (each back faces, then front faces): scene
    // objects, proxy, workspace box, bubble. Last the overlay: a panel and its text in pixels, on the screen plane
    // (same clip position in both eyes).
    const Pose& wp = scene.workpiece_pose;
    if (!is_rigid(wp))
        throw Error("renderer: SceneView.workpiece_pose must be finite with a unit orientation");
    im.add_workpiece(scene, fr, list);
    im.add_tiles(scene, eyes, list, stats);
    TileDrawEyes te;
    te.strategy = strategy();
    te.eye_count = scene.eye_count;
    te.frusta = eyes.frusta;
    add_indirect_tile_draws(scene, in_model_frame(te, scene.workpiece_pose), list, stats);
    im.add_tool(scene, list);
    add_force_arrow(scene, im.cylinder, im.cone, list);
    const std::vector<std::size_t> translucent_objects = im.add_objects(scene, list);
    im.add_translucent_items(scene, translucent_objects, list);
    // On-top objects: in the world, without the depth test, over every 3D item and under the 2D overlay.
    for (const std::size_t i : translucent_objects) {
        const SceneObject& o = scene.objects[i];
        if (!o.on_top) continue;
        list.cover_all();
        list.add(PipelineKind::kOverlay, im.objects[i].mesh, o.world_from_model, o.colour, o.lit).eye_mask = o.eyes & 0b11u;
    }
    im.add_overlay(scene, stats, fr, list);
    return im.submit(scene, slot, eyes.uniform, list, std::move(stats));
}

}  // namespace tridex::renderer
