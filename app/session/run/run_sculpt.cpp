// app/session/run/run_sculpt.cpp - the scripted hand and the session runtime of a run.
#include "app/session/run/run_sculpt.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <tuple>
#include <vector>

#include "app/scene/session_memory.hpp"
#include "app/scene/study_objects.hpp"
#include "app/scene/study_participant.hpp"
#include "app/scene/study_walls.hpp"
#include "app/scene/workpiece_list.hpp"
#include "app/scene/workpiece_source.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "devices/device_profiles.hpp"
#include "devices/registry/device_registry.hpp"

namespace tridex::app {

namespace {
constexpr std::size_t kMaxRecords = 120000;  // per-tick records kept: 2 minutes at 1 kHz

// A stroke of several passes is planned to stay within the device's reach: refuse one that would not.
void check_reach(const std::vector<Vec3>& path, const devices::DeviceProfile& profile) {
    constexpr double kSlack = 1e-6;  // m
    const Aabb& w = profile.workspace_m;
    for (const Vec3& p : path)
        for (int a = 0; a < 3; ++a)
            if (p[a] < w.lo[a] - kSlack || p[a] > w.hi[a] + kSlack)
                throw Error("stroke: the hand would leave the " + profile.name + "'s workspace (axis " + "xyz"[a] +
                            " reaches " + format_number(1e3 * p[a]) + " mm, the device reaches " +
                            format_number(1e3 * w.lo[a]) + ".." + format_number(1e3 * w.hi[a]) +
                            " mm); use a shorter stroke.length_m or a smaller clearance_m");
}
}  // namespace

double fit_workspace_scale(const Aabb& reach_m, const devices::DeviceProfile& profile) {
    constexpr double kUse = 0.9;  // of the workspace, leaving 5 % on each side
    const Vec3 room = profile.workspace_m.hi - profile.workspace_m.lo;
    if (!(room.x > 0.0 && room.y > 0.0 && room.z > 0.0))
        throw Error("workspace.scale: \"fit\" needs a device with a workspace (the " + profile.name + " profile has none)");
    if (reach_m.empty()) return 1.0;
    const Vec3 need = reach_m.hi - reach_m.lo;
    double s = 1.0;
    for (int a = 0; a < 3; ++a) s = std::max(s, need[a] / (kUse * room[a]));
    return s;
}

SculptBackend::SculptBackend(const RunScene& scene, double mesh_interval_s, MeshForm form, const SculptOptions& booleans,
                             gpu::Context* render_context, std::shared_ptr<devices::DTrackReceiver> tool_dtrack) {
    SessionSpec spec = scene.spec;
    const RunStudy& study = scene.study;
    // A study scene's felt walls, or a mesh or a saved model (checksums for a replay).
    check_session_memory_up_front(spec, SessionKind::kLive);  // a lattice too fine is refused before its scan conversion
    Workpiece wp = prepare_session_workpiece(spec);
    check_session_memory_of(wp.model, wp.resolution, SessionKind::kLive);  // before its contour, the session's largest part
    std::vector<Workpiece> more = prepare_more_workpieces(spec);  // a scene's further workpieces
    for (const Workpiece& m : more) check_session_memory_of(m.model, m.resolution, SessionKind::kLive);
    loaded_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    const devices::DeviceProfile profile = device_profile(spec.device);
    // The hand's path in device coordinates (the device's home, its workspace centre, on the stroke's
    // middle), or, without a stroke, a hand at rest at home a tool diameter plus a clearance in front of
    // the workpiece (+z).
    const Vec3 home = devices::home_position_m(profile);
    std::vector<double> t_s;
    std::vector<Vec3> path;
    std::optional<devices::ButtonScript> buttons;
    Vec3 centre;
    // A person moves the hand (a pointer, a rate device, a tracked tool): no scripted stroke.
    // A tracked tool: its device frame is the world (the display's calibration maps tracker to wall = world).
    const devices::DriverCapabilities& caps = driver_caps(spec.device_driver);
    const bool tracked = caps.input == devices::InputKind::kTracked;
    const bool live = devices::person_moves_hand(caps.input);
    // A "fit" workspace scale for a device whose hand moves in its workspace (not a rate or cursor device).
    auto fit_to = [&](Aabb reach) {
        if (scene.workspace_fit && !live) spec.workspace_scale = fit_workspace_scale(reach, profile);
    };
    if (study.enabled) {
        // The wand's flat end (its bottom point, the tool centre) half a wand length below the centre the scripted
        // participant steers; a person's device starts there too, at the start cap.
        const Vec3 half(0.0, 0.5 * study.scene.wand_length_m, 0.0);
        const study::ParticipantPath pp = study::scripted_participant_path(study.scene, study.seed, study.trial);
        Aabb reach;
        for (const Vec3& c : pp.centre_m) reach.add(c - half);
        centre = reach.centre();
        start_m_ = pp.centre_m.front() - half;
        // A person must reach the whole passage, its mouths and the wand's top point too.
        fit_to(reach.inflated(0.5 * study.scene.tube.funnel_mouth_m + study.scene.wand_length_m));
        // The simulated hand (of the simulated device, or holding the emulated Falcon's grip) plays the scripted
        // participant; a person's device (or hardware) has no scripted hand.
        if (caps.input != devices::InputKind::kScripted) {
            t_s = {0.0};
            path = {home + (start_m_ - centre) / spec.workspace_scale};
        } else {
            t_s = pp.t_s;
            for (const Vec3& c : pp.centre_m) path.push_back(home + (c - half - centre) / spec.workspace_scale);
            try {
                check_reach(path, profile);
            } catch (const Error& e) {
                throw Error(scene.source + ": field 'study': the scripted participant cannot reach the tube (" + e.what() +
                            "); use the wand profile, a smaller tube or \"workspace\": {\"scale\": \"fit\"}");
            }
            stroke_ticks_ = static_cast<std::size_t>(std::llround(pp.t_s.back() / spec.period_s));
        }
    } else if (scene.has_stroke && !live) {
        StrokePlan plan;
        try {
            const std::size_t k = scene.stroke_workpiece;  // the workpiece it is planned on
            plan = plan_stroke(k == 0 ? wp.model : more.at(k - 1).model, scene.stroke);
            place_plan(plan, workpiece_pose(spec_for_workpiece(spec, k)));
        } catch (const Error& e) {  // "stroke.duration_s: ...": the scene's field
            throw Error(scene.source + ": " + e.what());
        }
        Aabb reach;
        for (const Vec3& p : plan.world_m) reach.add(p);
        fit_to(reach);
        centre = plan.centre_m;
        t_s = plan.t_s;
        for (const Vec3& d : plan.device_offsets_m(spec.workspace_scale)) path.push_back(home + d);
        if (scene.stroke.passes > 1) check_reach(path, profile);
        if (!plan.buttons.empty()) buttons.emplace(plan.buttons);
        start_m_ = plan.world_m.front();
        stroke_ticks_ = static_cast<std::size_t>(std::llround(scene.stroke.end_s() / spec.period_s));
    } else {
        const Aabb box = placed(wp.model.lattice.bounds(), workpiece_pose(spec));
        fit_to(box);
        centre = Vec3(box.centre().x, box.centre().y, box.hi.z + 2.0 * tool_reach_m(spec.tool) + 0.01);
        t_s = {0.0};
        path = {home};
        start_m_ = centre;
    }
    if (tracked) {  // world = device: gain 1, no offset; the tool is drawn at the workspace centre until tracked
        spec.workspace_mode = "scaling";
        spec.workspace_scale = 1.0;
        centre = home;
        start_m_ = home;
    }
    spec.device_origin_m = centre - spec.workspace_scale * home;
    devices::DeviceInputs inputs;
    inputs.period_s = spec.period_s;
    inputs.hand_path.emplace(t_s, path);
    inputs.buttons = buttons;
    inputs.options = scene.device_options;
    if (tracked) {
        inputs.dtrack = std::move(tool_dtrack);
        inputs.dtrack_port = scene.tracked_port;
        inputs.dtrack_bind = scene.tracked_bind;
        inputs.tracked_tool.id = scene.tracked_id;
        inputs.tracked_tool.timeout_s = scene.tracked_timeout_s;
        inputs.tracked_tool.tracker_to_device = scene.display.tracker_to_wall;
    }
    std::unique_ptr<devices::HapticDevice> device = make_device(spec, inputs);
    // A served device maps through the scene's profile (its workspace): it must be the one the server serves.
    if (caps.input == devices::InputKind::kRemote && device->profile().name != profile.name) {
        const std::string served = devices::profile_name_of(device->profile().name);
        throw Error("--device net:" + spec.device_serial + ": the device server serves '" + device->profile().name +
                    "', the scene's device.profile is '" + spec.device + "' (" + profile.name + ")" +
                    (served.empty() ? std::string("; tridex does not know its workspace")
                                    : "; set device.profile to '" + served + "'"));
    }
    if (caps.app_sets_hand) mouse_ = dynamic_cast<devices::MouseDevice*>(device.get());
    RuntimeOptions ro;
    ro.sculpt = booleans;
    ro.render_context = render_context;
    ro.publish_meshes = true;
    ro.mesh_form = form;
    ro.mesh_interval_s = mesh_interval_s;
    ro.max_ticks = live ? kMaxRecords : std::min(kMaxRecords, stroke_ticks_ + stroke_ticks_ / 2 + 1000);
    // A person's study trial is recorded whole, up to the protocol's trial timeout.
    if (study.enabled && live)
        ro.max_ticks = std::max(ro.max_ticks, static_cast<std::size_t>((study.scene.protocol.trial_timeout_s + 10.0) / spec.period_s));
    if (!render_context && !booleans.cpu) ro.sculpt.cpu_contour = true;  // no renderer to draw GPU buffers
    runtime_ = std::make_unique<SessionRuntime>(spec, std::move(wp), std::move(more), std::move(device), start_m_, ro);
}

bool SculptBackend::stroke_done() const {
    if (runtime_->started() && !runtime_->loop_running()) return true;
    return stroke_ticks_ > 0 && runtime_->loop_stats().ticks >= stroke_ticks_;
}

Aabb SculptBackend::start_box_m() const {
    const haptics::HapticLoopConfig& cfg = runtime_->config();
    const devices::DeviceProfile& profile = runtime_->profile();
    const Vec3 c = cfg.device_to_world.position;
    return Aabb{profile.workspace_m.lo * cfg.workspace_scale + c, profile.workspace_m.hi * cfg.workspace_scale + c};
}

}  // namespace tridex::app
