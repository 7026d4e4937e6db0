// renderer/stereo/frame_draws.cpp - the draw list of one stereo frame and its opaque regions.
#include "renderer/stereo/frame_draws.hpp"

#include <algorithm>

namespace tridex::renderer {

FrameDraws::FrameDraws(const std::array<Mat4, 2>& clip_from_world, int width, int height)
    : clip_from_world_(clip_from_world), width_(width), height_(height) {}

void FrameDraws::cover(std::uint32_t mask, const Aabb& box_m) {
    for (int e = 0; e < 2; ++e)
        if (mask & (1u << e))
            opaque_region_[e] = unite(opaque_region_[e], project_box(clip_from_world_[e], box_m, width_, height_));
}

void FrameDraws::cover_all() { opaque_region_.fill(whole_image(width_, height_)); }

void FrameDraws::cover_drawn(std::uint32_t mask, const Aabb& box_m) {
    for (int e = 0; e < 2; ++e)
        if (mask & (1u << e))
            drawn_extra_[e] = unite(drawn_extra_[e], project_box(clip_from_world_[e], box_m, width_, height_));
}

void FrameDraws::cover_drawn(const PixelRect& rect) {
    const PixelRect image = whole_image(width_, height_);
    const PixelRect r{std::max(rect.x0, image.x0), std::max(rect.y0, image.y0), std::min(rect.x1, image.x1),
                      std::min(rect.y1, image.y1)};
    if (!r.empty()) screen_rects_.push_back(r);
}

std::vector<PixelRect> FrameDraws::drawn_rects(std::uint32_t mask) const {
    PixelRect world;
    for (int e = 0; e < 2; ++e)
        if (mask & (1u << e)) world = unite(world, unite(opaque_region_[e], drawn_extra_[e]));
    std::vector<PixelRect> out;
    if (!world.empty()) out.push_back(world);
    for (const PixelRect& r : screen_rects_) out.push_back(r);
    return out;
}

void FrameDraws::cover_drawn_all() { drawn_extra_.fill(whole_image(width_, height_)); }

StereoDraw& FrameDraws::add(PipelineKind kind, const GpuMesh& mesh, const glm::mat4& model, const glm::vec4& colour,
                            bool lit) {
    StereoDraw d;
    d.kind = kind;
    const GpuMesh::DrawRange r = mesh.draw_range();
    d.vertices = r.vertices;
    d.indices = r.indices;
    d.first_index = r.first_index;
    d.vertex_offset = r.vertex_offset;
    d.index_count = mesh.index_count();
    d.constants.world_from_model = model;
    d.constants.colour = colour;
    d.constants.lit = lit ? 1u : 0u;
    draws_.push_back(d);
    return draws_.back();
}

void FrameDraws::add_translucent(const GpuMesh& mesh, const glm::mat4& model, const glm::vec4& colour, bool lit) {
    add(PipelineKind::kTranslucentBack, mesh, model, colour, lit);
    add(PipelineKind::kTranslucentFront, mesh, model, colour, lit);
}

}  // namespace tridex::renderer
