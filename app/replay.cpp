// app/replay.cpp - replaying a recorded session.
#include "app/replay.hpp"

#include <chrono>

#include "app/session_settings.hpp"
#include "devices/recording.hpp"
#include "devices/replay_device.hpp"

namespace tridex::app {

void run_replay(const std::string& recording_path, const OutputOptions& out, const SculptOptions& sculpt) {
    const auto t_start = std::chrono::steady_clock::now();
    check_image_size(out.width, out.height);
    const devices::Recording rec = devices::read_recording(recording_path);
    const SessionSettings s = settings_from_json(rec.header.notes, recording_path);
    const devices::DeviceProfile profile = device_profile(s.device);
    Workpiece wp = prepare_workpiece(s.mesh_path, s.resolution, s.stock_m, s.workpiece_centre_m);
    devices::ReplayDevice device(profile, devices::device_states(rec));
    const haptics::HapticLoopConfig cfg = loop_config(s, rec.ticks.size() + 1000);
    const Vec3 start = rec.ticks.empty() ? s.device_origin_m : rec.ticks.front().wand_centre_m;
    // Until the replay device runs out of samples (it then "vanishes"); wall time is a safety net.
    const double timeout_s = 3.0 * static_cast<double>(rec.ticks.size()) * s.period_s + 10.0;
    const SessionRun run = run_session(wp, device, cfg, 0, timeout_s, start, SculptOptions{sculpt.cpu, out.validate, sculpt.cpu_contour, sculpt.gpu_contour});
    write_session_outputs(out, s, wp, run, cfg, profile, t_start);
}

}  // namespace tridex::app
