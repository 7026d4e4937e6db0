// app/commands/study/study_sim.cpp - the scripted participant driven through the haptic loop in device time.
#include "app/commands/study/study_sim.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "app/session/runtime/frame_loop.hpp"
#include "app/session/record/session_recording.hpp"
#include "app/scene/session_spec.hpp"
#include "app/scene/study_objects.hpp"
#include "app/scene/study_participant.hpp"
#include "app/scene/study_walls.hpp"
#include "compute/runtime/active_surface_publish.hpp"
#include "core/error.hpp"
#include "core/spsc_ring.hpp"
#include "core/triple_buffer.hpp"
#include "devices/device_profiles.hpp"
#include "devices/simulated_device.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app::study {

SimulatedPass simulate_pass(const StudyScene& scene, const std::string& model, std::uint32_t seed, int trial,
                            const ParticipantPath* given) {
    const Tube tube(scene.tube);
    const Workpiece wp = felt_walls(tube, study_model(scene, model, "model"), scene.path);
    const ParticipantPath pp = given ? *given : scripted_participant_path(scene, seed, trial);

    SessionSpec spec;
    spec.mesh_path = scene.path;
    spec.device = "wand";
    spec.tool = ToolShape{ToolKind::kFlatEnd, scene.wand_radius_m, scene.wand_length_m, 0};
    spec.points = 2;
    spec.op = "none";
    spec.cutting = false;
    spec.static_friction = 0.0;
    spec.dynamic_friction = 0.0;
    const devices::DeviceProfile profile = device_profile(spec.device);
    const Vec3 home = devices::home_position_m(profile);
    // The flat end (the tool centre, the bottom point) half a wand below the centre the participant steers.
    const Vec3 half(0.0, 0.5 * scene.wand_length_m, 0.0);
    Aabb reach;
    for (const Vec3& c : pp.centre_m) reach.add(c - half);
    spec.device_origin_m = reach.centre() - home;
    std::vector<Vec3> path;
    for (const Vec3& c : pp.centre_m) {
        const Vec3 d = c - half - spec.device_origin_m;
        for (int a = 0; a < 3; ++a)
            if (d[a] < profile.workspace_m.lo[a] - 1e-6 || d[a] > profile.workspace_m.hi[a] + 1e-6)
                throw Error("study: the scripted participant's path leaves the wand's workspace (axis " +
                            std::string(1, "xyz"[a]) + "); use a smaller tube");
        path.push_back(d);
    }
    const double end_s = pp.t_s.back() + 0.2;
    const auto ticks = static_cast<std::size_t>(std::ceil(end_s / spec.period_s));

    devices::SimulatedDevice device(profile, devices::ScriptedPath(pp.t_s, path), {}, spec.period_s);
    TripleBuffer<ActiveSurface> surface;
    SpscRing<ToolSample> ring(1024);
    haptics::HapticLoopConfig cfg = loop_config(spec, ticks);
    cfg.request_realtime = false;
    haptics::HapticLoop loop(device, surface, ring, cfg);
    const double extent = compute::tool_extent_m(scene.wand_length_m, scene.wand_radius_m);
    Vec3 centre = pp.centre_m.front() - half;
    SimulatedPass out;
    ToolSample drained;
    // In device time, through the one frame loop: a frame is one tick, run as fast as it computes; a sample the
    // device could not give ends the pass.
    bool ended = false;
    FrameFunctions frames([&] { return !ended; }, [&](std::uint64_t f) { return f + 1 >= ticks; },
                          [&](std::uint64_t f) {
                              const std::size_t i = static_cast<std::size_t>(f);
                              if (i % 5 == 0) {
                                  compute::extract_active_surface(wp.model, centre, extent, i + 1, surface.back());
                                  surface.publish();
                              }
                              const haptics::TickRecord r = loop.step(spec.period_s * static_cast<double>(i));
                              while (ring.try_pop(drained)) {
                              }
                              if (!r.valid_sample) {
                                  ended = true;
                                  return;
                              }
                              centre = r.hip_m;
                              out.contact_ticks += r.points_in_contact > 0;
                              out.max_force_n = std::max(out.max_force_n, glm::length(r.force_n));
                              out.tube_touch_ticks +=
                                  study_contact(tube, r.points[0].world_m, r.points[1].world_m, 0.0).tube;
                          });
    run_frames(frames, FramePacing{spec.period_s, false});
    loop.stop();
    out.ticks = std::min(ticks, loop.records().size());
    std::vector<haptics::TickRecord> records(loop.records().begin(), loop.records().begin() + static_cast<long>(out.ticks));
    out.recording = session_recording(spec, records);
    out.duration_s = out.recording.ticks.empty() ? 0.0 : out.recording.ticks.back().t_s - out.recording.ticks.front().t_s;
    return out;
}

}  // namespace tridex::app::study
