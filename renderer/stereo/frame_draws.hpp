// renderer/stereo/frame_draws.hpp - the draws of one stereo frame as they are collected, and the pixels the opaque
// ones may cover in each eye.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/aabb.hpp"
#include "core/math.hpp"
#include "renderer/scene/gpu_mesh.hpp"
#include "renderer/stereo/screen_region.hpp"
#include "renderer/stereo/stereo_frame.hpp"

namespace tridex::renderer {

/// The draw list of one stereo frame (record_stereo_frame draws it in this order within each phase), and per eye the
/// pixel rectangle its opaque draws may cover: where the ambient occlusion runs. Items without cheap bounds (a
/// whole-mesh workpiece, a mesh tool, scene objects) widen it to the whole image (cover_all).
class FrameDraws {
public:
    /// For the eyes' clip-from-world matrices (world m -> Vulkan clip space; 0 left, 1 right) and eye images of
    /// width x height pixels.
    FrameDraws(const std::array<Mat4, 2>& clip_from_world, int width, int height);

    /// Widens the opaque region of the eyes in `mask` (bit 0 left, bit 1 right) by the pixels `box_m` (world m) can
    /// cover (project_box).
    void cover(std::uint32_t mask, const Aabb& box_m);
    /// Widens both eyes' opaque regions to the whole image.
    void cover_all();
    /// Widens only the drawn region (drawn_region) of the eyes in `mask` by the pixels `box_m` can cover: for items
    /// drawn after the ambient occlusion (translucent ones).
    void cover_drawn(std::uint32_t mask, const Aabb& box_m);
    /// Adds `rect` (pixels; a screen-space item, the same in both eyes) to the drawn rectangles, or widens both
    /// eyes' drawn regions to the whole image.
    void cover_drawn(const PixelRect& rect);
    void cover_drawn_all();

    /// Appends a draw of all of `mesh` with pipeline `kind`, world-from-model `model` (m), linear RGBA `colour`, lit
    /// (Blinn-Phong) or flat. Returns it for further settings; the reference holds until the next append.
    StereoDraw& add(PipelineKind kind, const GpuMesh& mesh, const glm::mat4& model, const glm::vec4& colour, bool lit);
    /// Appends a translucent item as two draws: its back faces, then its front faces.
    void add_translucent(const GpuMesh& mesh, const glm::mat4& model, const glm::vec4& colour, bool lit);
    /// Appends a draw made by the caller (e.g. an indirect one).
    void add(const StereoDraw& draw) { draws_.push_back(draw); }

    /// The draws so far, in order.
    std::vector<StereoDraw>& draws() { return draws_; }
    /// Per eye, the pixels the opaque draws may cover (empty when none).
    const std::array<PixelRect, 2>& opaque_region() const { return opaque_region_; }
    /// Rectangles whose union holds every pixel any draw may cover in the eyes in `mask` (the opaque region, the
    /// cover_drawn items): outside them the eye images keep the clear colour. The world items' bounds, then each
    /// screen-space rectangle; empty ones left out.
    std::vector<PixelRect> drawn_rects(std::uint32_t mask) const;

private:
    std::array<Mat4, 2> clip_from_world_;
    int width_ = 0, height_ = 0;
    std::vector<StereoDraw> draws_;
    std::array<PixelRect, 2> opaque_region_{};
    std::array<PixelRect, 2> drawn_extra_{};  // cover_drawn items in world space
    std::vector<PixelRect> screen_rects_;     // cover_drawn screen-space rectangles
};

}  // namespace tridex::renderer
