// app/session/report/film_strip.cpp - the journal replayed to evenly spaced moments, each rendered, side by side in one PNG.
#include "app/session/report/film_strip.hpp"

#include <algorithm>
#include <cstring>

#include "app/session/view/framing.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/model/volume.hpp"
#include "core/error.hpp"
#include "gpu/context.hpp"
#include "renderer/image/image.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

namespace {

// The demo's viewpoint (session.cpp's final picture): 0.65 m in front of the wall, 0.15 m up.
const Vec3 kStripHead{0.0, 0.15, 0.65};

}  // namespace

void check_film_strip_options(const FilmStripOptions& o) {
    if (o.frames < 2 || o.frames > 24) throw Error("film strip: frames must be 2..24, got " + std::to_string(o.frames));
    if (o.width < 16 || o.width > 2048 || o.height < 16 || o.height > 2048)
        throw Error("film strip: each picture must be 16..2048 px per side, got " + std::to_string(o.width) + "x" +
                    std::to_string(o.height));
    if (o.gap_px < 0 || o.gap_px > 64) throw Error("film strip: gap_px must be 0..64, got " + std::to_string(o.gap_px));
}

namespace {

// Per picture, the number of records applied before it: just before the first sample with an operation, after the
// last record, and evenly spaced in samples between.
std::vector<std::size_t> picture_records(const compute::Journal& j, int frames) {
    std::vector<std::uint64_t> samples_before(j.records.size() + 1, 0);  // samples in records [0, k)
    std::size_t first_op = j.records.size();
    for (std::size_t k = 0; k < j.records.size(); ++k) {
        samples_before[k + 1] = samples_before[k] + j.records[k].samples.size();
        if (first_op == j.records.size())
            for (const ToolSample& s : j.records[k].samples)
                if (s.op != ToolOp::kNone) first_op = k;
    }
    const std::uint64_t from = samples_before[first_op], to = samples_before.back();
    std::vector<std::size_t> out;
    for (int i = 0; i < frames; ++i) {
        const std::uint64_t want = from + (to - from) * static_cast<std::uint64_t>(i) / static_cast<std::uint64_t>(frames - 1);
        // The first k whose samples_before reaches `want` (records are applied whole).
        const auto it = std::lower_bound(samples_before.begin() + static_cast<std::ptrdiff_t>(first_op), samples_before.end(), want);
        out.push_back(static_cast<std::size_t>(it - samples_before.begin()));
    }
    return out;
}

// The last sample in records [0, k), or none.
const ToolSample* last_sample(const compute::Journal& j, std::size_t k) {
    for (std::size_t r = k; r-- > 0;)
        if (!j.records[r].samples.empty()) return &j.records[r].samples.back();
    return nullptr;
}

}  // namespace

FilmStrip write_film_strip(const std::string& path, const compute::Journal& journal, const Workpiece& start,
                           const ToolShape& tool, const compute::JournalApplyFrom& replay, const FilmStripOptions& opt,
                           gpu::Context& context) {
    check_film_strip_options(opt);
    FilmStrip strip;
    strip.records = picture_records(journal, opt.frames);
    strip.width = opt.frames * opt.width + (opt.frames - 1) * opt.gap_px;
    strip.height = opt.height;
    renderer::Image out = renderer::Image::filled(strip.width, strip.height, 255, 255, 255);
    auto rend = renderer::OffscreenStereoRenderer::create(context, opt.width, opt.height);
    Pose head;
    head.position = kStripHead;
    const renderer::Screen screen = framing_screen(renderer::Screen::powerwall(), start.model.lattice.bounds(),
                                                   head.position, static_cast<double>(opt.width) / opt.height);
    const MenuItem menu_root = default_menu();
    MenuDrawing menu;  // kept across pictures: a changed menu gets new meshes, so the renderer uploads them
    for (int i = 0; i < opt.frames; ++i) {
        const std::size_t k = strip.records[static_cast<std::size_t>(i)];
        compute::TriDexel model = start.model;
        compute::JournalApplyFrom from = replay;
        from.record = 0;
        from.last_serial = 0;
        from.history_budget_bytes = std::size_t{1} << 40;  // every undo in the journal finds its stroke
        (void)compute::journal_apply(model, std::span<const compute::JournalRecord>(journal.records.data(), k), from);
        std::fill(model.tiles.dirty.begin(), model.tiles.dirty.end(), std::uint8_t{1});
        compute::Contourer contourer(model);
        contourer.update(model);
        const TriMesh mesh = contourer.mesh();
        const std::vector<std::uint8_t> materials = contourer.mesh_materials();
        renderer::SceneView view;
        view.workpiece = &mesh;
        view.workpiece_materials = &materials;
        view.show_workspace = false;
        view.eye_count = 1;
        view.occlusion_strength = opt.ao ? 1.0 : 0.0;
        const ToolSample* s = last_sample(journal, k);
        view.tool_shape = s ? s->tool : tool;
        view.tool_radius_m = view.tool_shape.radius_m;
        view.tool_centre_m = s ? s->position : start.model.lattice.bounds().centre() + Vec3(0.0, 0.0, 0.1);
        if (s) view.tool_orientation = s->orientation;
        std::vector<renderer::SceneObject> objects;
        if (opt.menu && s) menu.append(opt.menu->at(s->t_s), menu_root, objects);
        view.objects = objects;
        strip.menu_shown.push_back(!objects.empty());
        const renderer::StereoImages eyes = rend.render(view, screen, head, 0.0);
        for (int y = 0; y < opt.height; ++y)
            std::memcpy(out.at(i * (opt.width + opt.gap_px), y), eyes.left.at(0, y), static_cast<std::size_t>(opt.width) * 4);
        strip.t_s.push_back(s ? s->t_s : 0.0);
        strip.volume_m3.push_back(compute::dexel_volume_m3(model));
    }
    renderer::write_png(path, out);
    return strip;
}

}  // namespace tridex::app
