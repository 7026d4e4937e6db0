// app/commands/demo/elastic_demo.cpp - the scripted press of an elastic object, its images and its report.
#include "app/commands/demo/elastic_demo.hpp"
#include "app/session/runtime/frame_loop.hpp"
#include "app/session/view/framing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "app/support/json_file.hpp"
#include "app/support/output_dir.hpp"
#include "app/session/batch/session.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "core/primitives.hpp"
#include "gpu/context.hpp"
#include "haptics/elastic_object.hpp"
#include "haptics/forces/force_clamp.hpp"
#include "haptics/tool_points.hpp"
#include "renderer/camera/display_config.hpp"
#include "renderer/camera/off_axis.hpp"
#include "renderer/image/image.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

namespace {

namespace fs = std::filesystem;

constexpr double kPeriodS = 1e-3;       // the haptic rate, 1 kHz
constexpr int kSubdivisions = 5;        // drawn surface: 10242 vertices, about 1 mm apart on a 3 cm ball
constexpr double kSettleS = 0.1;        // still before the press and after the release, s
constexpr double kMaxScriptS = 600.0;   // longest press script, s
const Vec3 kHeadPosition{0.0, 0.15, 0.65};  // the viewer, world m (as the sculpting demo)

// One piece of the hand's script: press depth from p0 to p1 over duration_s; `step` marks the end of a hold.
struct Phase {
    double duration_s = 0.0;
    double p0 = 0.0, p1 = 0.0;
    bool step = false;
};

std::vector<Phase> press_script(const ScenePress& press, const std::string& source) {
    std::vector<Phase> phases;
    double p = -press.clearance_m;
    phases.push_back({kSettleS, p, p, false});
    for (double d : press.depths_m) {
        phases.push_back({std::fabs(d - p) / press.speed_m_s, p, d, false});
        phases.push_back({press.hold_s, d, d, true});
        p = d;
    }
    phases.push_back({std::fabs(p + press.clearance_m) / press.speed_m_s, p, -press.clearance_m, false});
    phases.push_back({std::max(press.hold_s, kSettleS), -press.clearance_m, -press.clearance_m, true});
    double total = 0.0;
    for (const Phase& ph : phases) total += ph.duration_s;
    if (!(total <= kMaxScriptS))
        throw Error(source + ": field 'press': the press lasts " + format_number(total) + " s; at most " +
                    format_number(kMaxScriptS) + " s (fewer depths, a faster speed_m_s or a shorter hold_s)");
    return phases;
}

// The tool's interaction points (a ball HIP, or an interaction mesh over the ball).
haptics::ToolPoints tool_points(const ElasticScene& s) {
    return s.points == 1 ? haptics::ToolPoints::single(s.tool_radius_m)
                         : haptics::ToolPoints::sphere_mesh(s.tool_radius_m, s.points);
}

// The tool centre at press depth p (m past first contact along the press direction).
Vec3 hip_at(const ElasticScene& s, double p) {
    const haptics::ElasticSphere& o = s.objects[static_cast<std::size_t>(s.press.object)].sphere;
    return o.centre_m - (o.radius_m + s.tool_radius_m - p) * s.press.direction;
}

// Every object's drawn surface for the tool at `hip`: the reference dented by the tool's contacts (elastic ones).
void draw_meshes(const ElasticScene& s, const std::vector<TriMesh>& reference, const Pose& hip,
                 std::vector<TriMesh>& drawn) {
    const haptics::ToolPoints pts = tool_points(s);
    drawn.resize(reference.size());
    for (std::size_t i = 0; i < reference.size(); ++i) {
        const SceneSphere& o = s.objects[i];
        const haptics::ElasticContacts c =
            o.elastic ? haptics::elastic_contacts(o.sphere, pts, hip) : haptics::ElasticContacts{};
        haptics::deform_elastic_mesh(reference[i], c, o.sphere.influence_m, drawn[i]);
    }
}

std::vector<TriMesh> reference_meshes(const ElasticScene& s) {
    std::vector<TriMesh> out;
    for (const SceneSphere& o : s.objects) out.push_back(icosphere_mesh(o.sphere.centre_m, o.sphere.radius_m, kSubdivisions));
    return out;
}

}  // namespace

ElasticPressRun run_elastic_press(const ElasticScene& s) {
    if (s.objects.empty() || s.press.object < 0 || s.press.object >= static_cast<int>(s.objects.size()))
        throw Error(s.source + ": field 'press.object': no such object");
    const SceneSphere& target = s.objects[static_cast<std::size_t>(s.press.object)];
    const std::vector<Phase> phases = press_script(s.press, s.source);
    const haptics::ToolPoints pts = tool_points(s);
    const TriMesh reference = icosphere_mesh(target.sphere.centre_m, target.sphere.radius_m, kSubdivisions);
    TriMesh drawn;
    ElasticPressRun run;
    // Each phase's ticks in order: (phase, k of n), k from 1.
    struct PressTick {
        const Phase* phase;
        std::size_t k, n;
    };
    std::vector<PressTick> schedule;
    for (const Phase& ph : phases) {
        const std::size_t n = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(ph.duration_s / kPeriodS)));
        for (std::size_t k = 1; k <= n; ++k) schedule.push_back({&ph, k, n});
    }
    // One tick of the press: the hand at its depth, the objects' forces, and at the end of a step the dented mesh.
    const auto press_tick = [&](std::size_t tick) {
        const Phase& ph = *schedule[tick].phase;
        const std::size_t k = schedule[tick].k, n = schedule[tick].n;
        ElasticTick t;
        t.t_s = static_cast<double>(tick) * kPeriodS;
        t.press_m = ph.p0 + (ph.p1 - ph.p0) * (static_cast<double>(k) / static_cast<double>(n));
        t.hip_m = hip_at(s, t.press_m);
        Pose pose;
        pose.position = t.hip_m;
        Vec3 f(0.0);
        haptics::ElasticContacts on_target;
        for (std::size_t i = 0; i < s.objects.size(); ++i) {
            const haptics::ElasticContacts c = haptics::elastic_contacts(s.objects[i].sphere, pts, pose);
            f += haptics::elastic_force(s.objects[i].sphere, c, s.max_force_n);
            if (static_cast<int>(i) == s.press.object) on_target = c;
        }
        t.force_n = haptics::clamp_force(f, s.max_force_n);
        t.penetration_m = on_target.max_depth_m();
        run.ticks.push_back(t);
        if (ph.step && k == n) {
            haptics::deform_elastic_mesh(reference, on_target, target.sphere.influence_m, drawn);
            ElasticStep st;
            st.press_m = t.press_m;
            st.penetration_m = t.penetration_m;
            st.force_n = glm::length(t.force_n);
            st.max_displacement_m = haptics::max_vertex_displacement_m(reference, drawn);
            if (run.steps.empty() || st.press_m > run.steps[run.deepest_step].press_m) {
                run.deepest_step = run.steps.size();
                run.deepest_tick = run.ticks.size() - 1;
            }
            run.steps.push_back(st);
        }
    };
    // In device time, through the one frame loop: a frame is one tick of the press, run as fast as it computes.
    FrameFunctions frames([] { return true; }, [&](std::uint64_t frame) { return frame + 1 >= schedule.size(); },
                          [&](std::uint64_t frame) { press_tick(static_cast<std::size_t>(frame)); });
    if (!schedule.empty()) run_frames(frames, FramePacing{kPeriodS, false});
    return run;
}

void run_elastic_demo(const ElasticDemoOptions& o) {
    check_image_size(o.width, o.height);
    const ElasticScene s = load_elastic_scene(o.scene);
    prepare_output_dir(o.out, "--out");
    const ElasticPressRun run = run_elastic_press(s);
    const ElasticStep& deepest = run.steps[run.deepest_step];
    const ElasticStep& released = run.steps.back();
    bool monotonic = true;
    for (std::size_t i = 1; i + 1 < run.steps.size(); ++i)
        monotonic = monotonic && run.steps[i].max_displacement_m > run.steps[i - 1].max_displacement_m;
    double max_force = 0.0, max_displacement = 0.0;
    for (const ElasticTick& t : run.ticks) max_force = std::max(max_force, glm::length(t.force_n));
    for (const ElasticStep& st : run.steps) max_displacement = std::max(max_displacement, st.max_displacement_m);

    // Both eyes at the deepest hold and after the release, framed on the objects and the tool's path.
    gpu::ContextOptions gopt;
    gopt.validation = o.validate;
    gpu::Context ctx = gpu::Context::create(gopt);
    auto renderer = renderer::OffscreenStereoRenderer::create(ctx, o.width, o.height);
    const std::vector<TriMesh> reference = reference_meshes(s);
    // One set of drawn meshes per image: the renderer uploads an object's mesh again only when its pointer or its
    // triangle count changes, so the released image must not reuse the dented meshes' storage.
    std::vector<TriMesh> drawn_deepest, drawn_released;
    Aabb box;
    for (const TriMesh& m : reference) box.add(m.bounds().lo), box.add(m.bounds().hi);
    box.add(hip_at(s, -s.press.clearance_m) - Vec3(s.tool_radius_m));
    box.add(hip_at(s, -s.press.clearance_m) + Vec3(s.tool_radius_m));
    Pose head;
    head.position = kHeadPosition;
    const renderer::Screen screen =
        framing_screen(renderer::Screen::powerwall(), box, head.position, static_cast<double>(o.width) / o.height);
    auto render_at = [&](const ElasticTick& t, std::vector<TriMesh>& drawn) {
        Pose hip;
        hip.position = t.hip_m;
        draw_meshes(s, reference, hip, drawn);
        std::vector<renderer::SceneObject> objects;
        for (std::size_t i = 0; i < drawn.size(); ++i)
            objects.push_back({&drawn[i], glm::vec4(glm::vec3(s.objects[i].colour), s.objects[i].alpha)});
        renderer::SceneView view;
        view.objects = objects;
        view.tool_centre_m = t.hip_m;
        view.tool_radius_m = s.tool_radius_m;
        view.tool_shape = ToolShape{ToolKind::kBall, s.tool_radius_m, 0.0, 0};
        view.show_workspace = false;
        view.force_N = t.force_n;
        return renderer.render(view, screen, head, renderer::kDefaultEyeSeparationM);
    };
    const renderer::StereoImages at_depth = render_at(run.ticks[run.deepest_tick], drawn_deepest);
    const renderer::StereoImages after = render_at(run.ticks.back(), drawn_released);
    const fs::path out(o.out);
    renderer::write_png((out / "left.png").string(), at_depth.left);
    renderer::write_png((out / "right.png").string(), at_depth.right);
    renderer::write_png((out / "sbs.png").string(), renderer::side_by_side(at_depth.left, at_depth.right));
    renderer::write_png((out / "released.png").string(), renderer::side_by_side(after.left, after.right));

    {
        const std::string csv = (out / "haptics.csv").string();
        std::ofstream f(csv);
        if (!f) throw Error(csv + ": cannot open for writing");
        f << "t_s,press_m,penetration_m,hip_x_m,hip_y_m,hip_z_m,force_x_n,force_y_n,force_z_n\n";
        char line[256];
        for (const ElasticTick& t : run.ticks) {
            std::snprintf(line, sizeof line, "%.4f,%.7f,%.7f,%.7f,%.7f,%.7f,%.6f,%.6f,%.6f\n", t.t_s, t.press_m,
                          t.penetration_m, t.hip_m.x, t.hip_m.y, t.hip_m.z, t.force_n.x, t.force_n.y, t.force_n.z);
            f << line;
        }
        if (!f) throw Error(csv + ": write failed");
    }

    const SceneSphere& target = s.objects[static_cast<std::size_t>(s.press.object)];
    nlohmann::json steps = nlohmann::json::array();
    for (std::size_t i = 0; i < run.steps.size(); ++i) {
        const ElasticStep& st = run.steps[i];
        steps.push_back({{"press_m", st.press_m}, {"penetration_m", st.penetration_m}, {"force_n", st.force_n},
                         {"max_displacement_m", st.max_displacement_m},
                         {"released", i + 1 == run.steps.size()}});
    }
    nlohmann::json r;
    r["scene"] = s.source;
    r["object"] = {{"name", target.name},
                   {"radius_m", target.sphere.radius_m},
                   {"stiffness_n_per_m", target.sphere.stiffness_n_per_m},
                   {"influence_radius_m", target.sphere.influence_m}};
    r["tool"] = {{"shape", "ball"}, {"radius_m", s.tool_radius_m}, {"points", s.points}};
    r["deformation"] = {{"max_displacement_m", max_displacement},
                        {"residual_displacement_m", released.max_displacement_m},
                        {"grows_monotonically", monotonic}};
    r["steps"] = steps;
    r["force"] = {{"max_n", max_force}, {"limit_n", s.max_force_n}, {"at_deepest_n", deepest.force_n}};
    r["ticks"] = run.ticks.size();
    r["rate_hz"] = 1.0 / kPeriodS;
    r["images"] = {"left.png", "right.png", "sbs.png", "released.png"};
    r["render"] = {{"device", ctx.device_name()},
                   {"eye_strategy", renderer.strategy_note()},
                   {"validation_messages", ctx.validation_messages()}};
    write_json_file((out / "report.json").string(), r);

    std::printf("tridex demo --elastic: pressed '%s' (r = %.1f mm, k = %.0f N/m, radius of influence %.1f mm) in %zu "
                "steps to %.1f mm, then released\n",
                target.name.c_str(), 1e3 * target.sphere.radius_m, target.sphere.stiffness_n_per_m,
                1e3 * target.sphere.influence_m, run.steps.size() - 1, 1e3 * deepest.press_m);
    for (std::size_t i = 0; i < run.steps.size(); ++i) {
        const ElasticStep& st = run.steps[i];
        std::printf("  %-9s press %5.1f mm  penetration %5.2f mm  force %5.2f N  dent %5.2f mm\n",
                    i + 1 == run.steps.size() ? "released" : ("step " + std::to_string(i + 1)).c_str(),
                    1e3 * st.press_m, 1e3 * st.penetration_m, st.force_n, 1e3 * st.max_displacement_m);
    }
    std::printf("  deformation: max %.3f mm, residual after release %.3g m%s\n", 1e3 * max_displacement,
                released.max_displacement_m, monotonic ? "" : " (did NOT grow with every step)");
    std::printf("  wrote %s/{left,right,sbs,released}.png, haptics.csv, report.json\n", o.out.c_str());
    if (ctx.validation_messages() > 0)
        std::fprintf(stderr, "tridex: %u Vulkan validation messages (report.json render.validation_messages)\n",
                     ctx.validation_messages());
}

}  // namespace tridex::app
