// app/session/report/film_strip.cpp - the journal replayed to moments spread over the stretch where it changed the
// model, each rendered, side by side in one PNG.
#include "app/session/report/film_strip.hpp"

#include <algorithm>
#include <cstring>

#include "app/session/report/strip_moments.hpp"
#include "app/session/view/framing.hpp"
#include "app/session/view/symmetry_view.hpp"
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
    const compute::Journal fine = split_batches(journal, kStripPieceSamples);
    // Progress: measuring what each record changes the first half, the pictures the second.
    strip.records = strip_picture_records(
        fine, record_changes(fine, start.model, strip_replay(replay), progress_part(opt.progress, 0.0, 0.5)),
        opt.frames);
    strip.width = opt.frames * opt.width + (opt.frames - 1) * opt.gap_px;
    strip.height = opt.height;
    renderer::Image out = renderer::Image::filled(strip.width, strip.height, 255, 255, 255);
    auto rend = renderer::OffscreenStereoRenderer::create(context, opt.width, opt.height);
    Pose head;
    head.position = kStripHead;
    const renderer::Screen screen = framing_screen(renderer::Screen::powerwall(), start.model.lattice.bounds(),
                                                   head.position, static_cast<double>(opt.width) / opt.height);
    const MenuItem menu_root = default_menu(opt.palette ? *opt.palette : default_material_palette());
    MenuDrawing menu;  // kept across pictures: a changed menu gets new meshes, so the renderer uploads them
    // One pass over the journal: the model and its contour follow the pictures (a Contourer redoes the dirty tiles
    // only, the same pieces as a whole re-contour).
    compute::TriDexel model = start.model;
    std::fill(model.tiles.dirty.begin(), model.tiles.dirty.end(), std::uint8_t{1});
    compute::JournalApplier applier(model, strip_replay(replay));
    compute::Contourer contourer(model);
    std::size_t applied = 0;
    const SymmetryGhosts ghosts(start.model.lattice.bounds(), nullptr);  // mesh tools: a ball stands in
    for (int i = 0; i < opt.frames; ++i) {
        const std::size_t k = strip.records[static_cast<std::size_t>(i)];
        applier.apply(std::span<const compute::JournalRecord>(fine.records.data() + applied, k - applied));
        applied = k;
        if (i + 1 == opt.frames) applier.flush();  // the last picture: a push group still held, applied
        contourer.update(model);
        const TriMesh mesh = contourer.mesh();
        const std::vector<std::uint8_t> materials = contourer.mesh_materials();
        renderer::SceneView view;
        view.workpiece = &mesh;
        view.workpiece_materials = &materials;
        view.palette = opt.palette;
        view.show_workspace = false;
        view.eye_count = 1;
        view.occlusion_strength = opt.ao ? 1.0 : 0.0;
        const ToolSample* s = last_sample(fine, k);
        view.tool_shape = s ? s->tool : tool;
        view.tool_radius_m = view.tool_shape.radius_m;
        view.tool_centre_m = s ? s->position : start.model.lattice.bounds().centre() + Vec3(0.0, 0.0, 0.1);
        if (s) view.tool_orientation = s->orientation;
        std::vector<renderer::SceneObject> objects;
        if (s) ghosts.append(s->symmetry, Pose{s->position, s->orientation}, view.tool_shape, objects);
        const std::size_t before_menu = objects.size();
        if (opt.menu && s) menu.append(opt.menu->at(s->t_s), menu_root, objects);
        view.objects = objects;
        strip.menu_shown.push_back(objects.size() > before_menu);
        const renderer::StereoImages eyes = rend.render(view, screen, head, 0.0);
        for (int y = 0; y < opt.height; ++y)
            std::memcpy(out.at(i * (opt.width + opt.gap_px), y), eyes.left.at(0, y), static_cast<std::size_t>(opt.width) * 4);
        strip.t_s.push_back(s ? s->t_s : 0.0);
        strip.volume_m3.push_back(compute::dexel_volume_m3(model));
        report_progress(progress_part(opt.progress, 0.5, 1.0), i + 1.0, opt.frames);
    }
    renderer::write_png(path, out);
    return strip;
}

}  // namespace tridex::app
