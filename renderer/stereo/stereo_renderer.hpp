// renderer/stereo/stereo_renderer.hpp - offscreen head-tracked stereo rendering of the sculpting scene.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/aabb.hpp"
#include "core/material_palette.hpp"
#include "core/math.hpp"
#include "core/pose.hpp"
#include "core/tool_shape.hpp"
#include "core/tri_mesh.hpp"
#include "gpu/context.hpp"
#include "gpu/indirect_workpiece.hpp"
#include "renderer/camera/off_axis.hpp"
#include "renderer/image/image.hpp"
#include "renderer/scene/tile_group_lod.hpp"
#include "renderer/scene/tile_mesh_cache.hpp"
#include "renderer/stereo/ambient_occlusion.hpp"
#include "renderer/stereo/eye_strategy.hpp"
#include "renderer/stereo/screen_region.hpp"
#include "renderer/timing/frame_stats.hpp"

namespace tridex::renderer {

/// A scene object drawn in one colour (a study scene's tube, funnels and caps): its mesh in world m (CCW from
/// outside) and its linear RGBA colour; alpha < 1 draws it translucent (back faces, then front faces, after the
/// opaque items), alpha = 1 opaque. The mesh is uploaded again only when the pointer or its triangle count
/// changes: keep it alive and unchanged while frames use it.
struct SceneObject {
    const TriMesh* mesh = nullptr;       ///< model m (world m with the default transform); nullptr or empty = not drawn
    glm::vec4 colour{1.0f};              ///< linear RGBA, each in [0, 1]
    /// The eyes that see it: bit 0 left, bit 1 right (0b11: both, an ordinary object). A one-eye object (a test
    /// pattern's eye labels) lands in that eye's image under every eye strategy; 0 draws nothing.
    std::uint32_t eyes = 0b11;
    /// Shaded by the key and fill lights (true) or drawn flat in its colour (false: marks and text that must keep
    /// their colour whichever way they face).
    bool lit = true;
    /// Drawn over the rest of the scene (no depth test, after every other 3D item, in the order given) while still
    /// placed in the world, so each eye sees it at its own depth: an in-scene menu that material must not hide.
    bool on_top = false;
    /// Model -> world transform the mesh is drawn with (m; a rigid pose, scaled where a unit mesh stands for a
    /// tool). Identity: the mesh is in world m. A mesh kept at one address is uploaded once, so a moving object
    /// moves by this transform.
    glm::mat4 world_from_model{1.0f};
};

/// What one frame shows (world metres, y up; the PowerWall screen in z = 0 facing +z).
struct SceneView {
    const TriMesh* workpiece = nullptr;  ///< the carved solid, model m; nullptr or empty = not drawn
    /// The workpiece's model frame -> world (m, rigid): `workpiece`, `tiles`, `tile_groups` and the indirect
    /// workpiece are in the model frame and drawn through it; culling and levels of detail use the eyes taken into
    /// that frame. Identity (the default): the model frame is the world.
    Pose workpiece_pose{};
    Vec3 tool_centre_m{0.0};             ///< centre of the ball tool, world m
    double tool_radius_m = 0;            ///< ball radius, m; <= 0 = no tool drawn
    /// The tool's shape: a ball draws a sphere of tool_radius_m at tool_centre_m; a flat-end mill draws its
    /// cylinder (tool frame of core/tool_shape.hpp: flat end at tool_centre_m, shank along the tool axis +y
    /// turned by tool_orientation) when tool_radius_m > 0; a mesh tool draws tool_mesh.
    ToolShape tool_shape{};
    Quat tool_orientation{1.0, 0.0, 0.0, 0.0};  ///< tool frame -> world (unit quaternion)
    /// A mesh tool (tool_shape kMesh): its mesh in the tool frame (m, CCW from outside), drawn as it is, turned
    /// by tool_orientation and placed at tool_centre_m (its reference point) when tool_radius_m > 0; uploaded
    /// again only when the pointer or its size changes (keep it alive and unchanged while frames use it).
    /// nullptr with kMesh: a ball of tool_radius_m (the mesh's bounding sphere) stands in.
    const TriMesh* tool_mesh = nullptr;
    bool show_workspace = true;          ///< draw the haptic workspace as a translucent box
    Aabb workspace_m;                    ///< the workspace, world m (an empty box is not drawn)
    /// The bubble of the bubble workspace technique (Dominjon et al. 2005): position control inside,
    /// rate control outside; drawn as a translucent sphere when bubble_radius_m > 0 (world m).
    Vec3 bubble_centre_m{0.0};
    double bubble_radius_m = 0.0;

    // ---- Materials, proxy, force, tiles, overlay. Defaults draw nothing new. ----
    /// Per-vertex material ids of `workpiece` (size = workpiece->positions.size(), ids 0..kMaterialCount-1,
    /// colours from `palette`); nullptr = every vertex material 0.
    const std::vector<std::uint8_t>* workpiece_materials = nullptr;
    /// The materials' names and colours (core/material_palette.hpp): the workpiece's vertex materials, and its flat
    /// colour (material 0) without them; nullptr = default_material_palette().
    const MaterialPalette* palette = nullptr;
    /// The proxy (god-object, Peng et al.: the IHIP held on the surface while the HIP goes inside), drawn as
    /// a translucent lit sphere of proxy_radius_m at proxy_m (world m) when proxy_radius_m > 0.
    Vec3 proxy_m{0.0};
    double proxy_radius_m = 0.0;
    /// Force on the user, N (world axes); drawn as an arrow from tool_centre_m along the force with length
    /// force_m_per_newton * |force_N| (m per N; default 0.02 m/N: the 3.3 N peak of an Omni-class device is a
    /// 6.6 cm arrow). No arrow when that length is below 1 um.
    Vec3 force_N{0.0};
    double force_m_per_newton = 0.02;
    /// The workpiece as tiles (one mesh per 16^3-cell contouring tile, world bounds, version): drawn in
    /// addition to `workpiece` (supply one or the other), each tile uploaded once and again only when its
    /// version changes, and drawn only in the eyes whose off-axis frustum its bounds may touch.
    std::span<const TileMesh> tiles{};
    /// Groups of neighbouring `tiles` with levels of detail over the whole group (TileGroup; each tile names
    /// its smallest group in TileMesh::group, each group its enclosing one): with `lod`, an eye draws a group's
    /// level instead of the tiles under it when that level's error projects to at most lod_max_px. Uploaded
    /// like tiles (by id and version). Empty = per-tile levels only.
    std::span<const TileGroup> tile_groups{};
    /// Further objects in their own colours (SceneObject), drawn with the tool and, when translucent, before
    /// the proxy. Empty = none.
    std::span<const SceneObject> objects{};
    /// false: draw every tile in both eyes (for comparison; counts then show nothing skipped).
    bool cull_tiles = true;
    /// Draw each tile in each eye at the coarsest of its TileMesh::levels whose error projects (pixels_per_metre
    /// of the tile's bounds in that eye's off-axis frustum and image) to at most lod_max_px pixels; false: always
    /// the full mesh. Multiview draws both eyes at once, so there a tile gets the finer of the two eyes' levels.
    bool lod = true;
    double lod_max_px = 1.0;  ///< pixels (> 0 and finite)
    /// The workpiece as GPU buffers (GPU contouring): each tile drawn with one vkCmdDrawIndexedIndirect in the
    /// eyes whose frustum its bounds may touch (cull_tiles), lit like the tiles above with palette colours but
    /// flat-shaded (facet normals from screen-space derivatives: the GPU contour has no normals). Counted in
    /// FrameStats tiles like `tiles`. nullptr = none. Its buffers must not change until draw()/render() return.
    const IndirectWorkpiece* indirect_workpiece = nullptr;
    /// true: `tiles` and `tile_groups` are indirect_workpiece's tiles read back (with their levels of detail, drawn
    /// in place of those tiles' indirect draws, which the caller leaves out of indirect_workpiece->tiles). They
    /// are then uploaded in its grid units and drawn through its world_from_grid (ModelFrame), so they meet its
    /// indirect tiles with bit-identical border vertices; they are smooth-shaded like `tiles` always are (vertex
    /// normals), while the indirect tiles are flat. Needs indirect_workpiece (else tridex::Error).
    bool tiles_from_indirect = false;
    /// Draw the 2D overlay (top left, on the screen plane: identical in both eyes) with the rates below,
    /// the frame time and, when there are tiles, the tiles drawn / skipped per eye.
    bool show_overlay = false;
    double haptic_rate_hz = -1.0;  ///< shown in the overlay; < 0 = unknown ("--")
    double sculpt_rate_hz = -1.0;  ///< shown in the overlay; < 0 = unknown ("--")
    double frame_time_ms = -1.0;   ///< shown in the overlay; < 0 = the renderer's previous FrameStats::frame_ms
    double overlay_scale = 0.0;    ///< overlay pixels per font unit; <= 0 = overlay_scale_for(height, height)
    std::string overlay_status;    ///< further overlay lines ('\n' between), e.g. what is saved and what is not
    /// With tiles: the overlay also counts the tiles drawn and skipped per eye (a developer's figure).
    bool overlay_tile_counts = true;
    /// Eyes to render: 2 = stereo; 1 = mono, one eye's work only: the left eye (at the head for a zero eye
    /// separation) is drawn into layer 0 and nothing into layer 1 (pass-per-eye and instanced-layer skip the
    /// right eye's pass / instances; multiview's render pass still covers both views). FrameStats then has
    /// only eye-0 passes and eye-0 tile counts; render() returns the one eye as both left and right.
    /// Other values throw tridex::Error.
    int eye_count = 2;
    /// Ambient occlusion (volumetric obscurance over the opaque phase, renderer/stereo/ambient_occlusion.hpp):
    /// the radius of the sphere around each surface point that is tested for solid, world m (about the size
    /// of the cuts to bring out), and the strength (0 = off; 1 = a half-filled sphere keeps its colour, a fully
    /// filled one is darkened to 0.3, an empty one brightened to 1.45). Non-finite or negative values throw.
    double occlusion_radius_m = 0.012;
    double occlusion_strength = 1.0;
    /// How finely the occlusion is evaluated: per 2x2 pixels (the default) or per 4x4 (a quarter of its first
    /// dispatch's work; a session on a frame-time budget chooses it, app/session/view/frame_budget.hpp).
    OcclusionResolution occlusion_resolution = OcclusionResolution::kHalf;
};

/// The two eyes' images of one frame, each width x height RGBA, and the frame's statistics.
struct StereoImages {
    Image left, right;
    FrameStats stats{};
};

/// Renders both eyes into one 2-layer colour image (+ depth) offscreen and reads them back: the workpiece
/// (whole mesh and/or per-eye culled tiles) lit (Blinn-Phong, a directional key light from above and a soft
/// fill light from the eye) with per-vertex normals (core vertex_normals) and per-material colours, the tool
/// as a ball, the force arrow (shaft cylinder + cone head, opaque), then screen-space ambient occlusion of
/// that opaque picture (SceneView::occlusion_*: cuts darken, edges and crests brighten), then translucent: the proxy sphere, the workspace box and the bubble
/// (alpha-blended: back faces, then front faces), then the screen-space overlay. Each render pass is
/// timed per phase (opaque, translucent, overlay) with GPU timestamp queries when the queue has them.
/// The eye strategy asked for is self-tested at creation (self_test_eye_strategy: each layer must
/// receive its own eye's draws, read back and checked); if it is unsupported or fails (Mesa 22.3 lavapipe
/// advertises multiview but draws view 1's clipped triangles into layer 0) the renderer falls back to
/// kPassPerEye and says so via strategy() / strategy_note(). Two frames in flight: each has its own command
/// buffer, fence, uniform buffer, descriptor sets, timestamp queries and per-frame meshes, so draw() records
/// and submits a frame without waiting for it (only for the frame two before, whose resources it reuses), and
/// tile or tool buffers that a change replaces are destroyed only once the frames that used them have finished.
/// Move-only (a moved-from renderer may only be destroyed or assigned); the Context must outlive it. One thread
/// at a time; render() is synchronous.
class OffscreenStereoRenderer {
public:
    /// Builds pipelines and a width x height stereo target, self-testing `preferred`.
    /// Throws tridex::Error when width/height are outside 1..device limit, when even kPassPerEye fails
    /// its self-test, or on a Vulkan failure.
    static OffscreenStereoRenderer create(gpu::Context& context, int width, int height,
                                          EyeStrategy preferred = EyeStrategy::kMultiview);

    ~OffscreenStereoRenderer();
    OffscreenStereoRenderer(OffscreenStereoRenderer&&) noexcept;
    OffscreenStereoRenderer& operator=(OffscreenStereoRenderer&&) noexcept;

    /// The strategy in use (after the self-test).
    EyeStrategy strategy() const;
    /// One line: what was asked for, what the self-test saw, what is used and why.
    std::string strategy_note() const;
    int width() const;   ///< image width, pixels
    int height() const;  ///< image height, pixels
    /// Changes the eye image size to width x height pixels (a window was resized): waits for the frames in flight,
    /// then rebuilds the colour and depth target and the ambient-occlusion images; pipelines, tile meshes and
    /// statistics stay. Nothing changes when the size is the same. colour_image() holds no frame until the next
    /// draw(), and last_images() throws until then. Throws tridex::Error as create() does for a bad size (the old target is
    /// kept then) or on a Vulkan failure.
    void resize(int width, int height);
    /// How many times resize() has made a new target: a view of colour_image() taken before another value of it may
    /// have been destroyed (a new view can reuse its handle value).
    std::uint64_t target_generation() const;

    /// Renders one stereo frame: eyes at eye_positions(head, eye_separation_m), each with the off-axis
    /// frustum through `screen` (off_axis_view, near_m/far_m in m); waits for the GPU and returns both images.
    /// Throws tridex::Error on invalid input (eye on/behind the screen, bad near/far or separation, bad
    /// mesh indices, non-finite tool or workspace) or on a Vulkan failure.
    StereoImages render(const SceneView& scene, const Screen& screen, const Pose& head, double eye_separation_m,
                        double near_m = 0.05, double far_m = 20.0);

    /// As render(), but submits the frame without waiting for it (no eye Images are built on the CPU): for
    /// presenting through colour_image() with GPU blits recorded in later submissions on the Context's queue.
    /// Same arguments and errors as render(). Returns the frame's statistics (tiles drawn / skipped per eye,
    /// uploads) with the timings (timing, frame_ms, passes) of the latest frame that has finished (none before
    /// the first; finish() gives this frame's own); also kept as last_frame_stats(). With
    /// SceneView::indirect_workpiece it waits for the frame (those buffers may change once it returns).
    FrameStats draw(const SceneView& scene, const Screen& screen, const Pose& head, double eye_separation_m,
              double near_m = 0.05, double far_m = 20.0);
    /// Waits for the last frame drawn and returns its statistics with its own timings (as last_frame_stats()
    /// then). Throws tridex::Error on a Vulkan failure or when the GPU takes over 10 s.
    FrameStats finish();
    /// Statistics (with their own timings) of the frames seen finished since the last call, oldest first: every
    /// frame appears once, after a later draw(), finish(), render() or last_images() saw it done.
    std::vector<FrameStats> take_finished_frames();

    /// The 2-layer colour image (R8G8B8A8_UNORM, width() x height(), layer 0 = left eye, layer 1 = right eye,
    /// usage COLOR_ATTACHMENT | TRANSFER_SRC | SAMPLED). After render()/draw() it holds the last frame in
    /// VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL once the frame's submission has run; callers may record transfer reads
    /// (blits, copies) of it in later submissions on the Context's queue, which the next frame's render pass
    /// waits for (its external subpass dependency covers transfer reads). Do not change its layout.
    VkImage colour_image() const;
    /// A 2D_ARRAY view of colour_image()'s two layers (the image is also SAMPLED). To sample it, move the image
    /// to SHADER_READ_ONLY_OPTIMAL and back to TRANSFER_SRC_OPTIMAL in the same submission (AnaglyphPass).
    VkImageView colour_array_view() const;
    /// The last frame's eyes, as render() returns them (mono: the one eye as both) with last_frame_stats(): waits
    /// for that frame, then copies its colour layers to a host buffer in a submission of its own (once per frame;
    /// frames are not copied back otherwise). Throws tridex::Error before the first frame or on a Vulkan failure.
    StereoImages last_images() const;
    /// Frames rendered so far by render()/draw() (0: colour_image() holds no frame and is in UNDEFINED layout).
    std::uint64_t frames_rendered() const;
    /// GPU time of the latest finished frame's recorded work (render passes and ambient occlusion of both eyes),
    /// ms, from timestamp queries at the top and bottom of the frame; negative when the device has no
    /// timestamps or no frame has finished yet (render() and finish() wait for theirs).
    double last_gpu_ms() const;
    /// Statistics of the last frame drawn (default-constructed before the first): its own timings once it has
    /// finished and that was seen (render(), finish(), last_images()), else the latest finished frame's.
    const FrameStats& last_frame_stats() const;
    /// Rectangles holding every pixel of the last frame drawn that may differ from the clear colour, in either eye
    /// (opaque and translucent items' bounds, the overlay's panel); empty before the first frame and for a frame
    /// that drew nothing. Outside them both eye images hold clear_codes().
    const std::vector<PixelRect>& last_drawn_rects() const;
    /// The colour every frame is cleared to, as the 8-bit codes the colour image stores (R, G, B).
    static std::array<std::uint8_t, 3> clear_codes();
    /// True when the queue family supports timestamp queries (timestampValidBits > 0 and the Context enabled them).
    bool gpu_timestamps_available() const;
    /// Use GPU timestamps when available (true, the default) or the CPU clock (false: FrameStats then holds
    /// one "frame" time measured from submission until the renderer saw the frame finished, and last_gpu_ms() is
    /// negative).
    void set_gpu_timestamps(bool use);
    /// Tile meshes uploaded since creation (see SceneView::tiles).
    std::uint64_t tile_uploads_total() const;
    /// Tile vertex and index buffers alive now (2 per non-empty tile of the last frame).
    std::size_t tile_buffers() const;
    /// VkDeviceMemory allocations holding those buffers (blocks of the tile buffer pool, a few MiB each).
    std::size_t tile_memory_blocks() const;

    struct Impl;

private:
    explicit OffscreenStereoRenderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace tridex::renderer
