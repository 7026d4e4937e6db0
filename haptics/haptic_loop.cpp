// haptics/haptic_loop.cpp - the haptic thread: absolute-deadline ticks and the per-tick pipeline
// (workspace mapping, contact, filter, safety stages, telemetry).
#include "haptics/haptic_loop.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <sys/prctl.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <limits>
#include <string>

#include "core/cpu_reservation.hpp"
#include "core/error.hpp"
#include "core/thread_name.hpp"
#include "haptics/forces/force_clamp.hpp"
#include "haptics/realtime.hpp"

namespace tridex::haptics {

namespace {

// Touches 128 KiB of the calling thread's stack below this frame, a page at a time, so that those pages are mapped
// (and, under mlockall, locked) before the first tick: no tick takes a page fault on its own stack.
[[gnu::noinline]] void prefault_stack() {
    volatile unsigned char pad[128 * 1024];
    for (std::size_t i = 0; i < sizeof pad; i += 4096) pad[i] = 0;
}

bool finite_state(const devices::DeviceState& s) {
    const Quat& q = s.pose.orientation;
    return std::isfinite(s.t_s) && is_finite(s.pose.position) && is_finite(s.velocity_m_s) && std::isfinite(q.w) &&
           std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
}

[[noreturn]] void bad(const std::string& field, double value, const char* rule) {
    throw Error("HapticLoopConfig." + field + " = " + std::to_string(value) + " " + rule);
}

// A rigid pose: a finite position and a unit quaternion (renormalised to the last bit); bad() names `field` otherwise.
void check_rigid(Pose& p, const std::string& field) {
    if (!is_finite(p.position)) bad(field + ".position.x", p.position.x, "(or y, z) is not finite");
    const Quat& q = p.orientation;
    const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    if (!is_unit(q)) bad(field + ".orientation |q|", n, "must be 1 (unit quaternion)");
    p.orientation = q / n;
}

// How much stiffer the device feels a world stiffness: the workspace scale, except in kScaling, whose forces reach
// the device divided by it (world_stiffness_cap_n_per_m).
double device_gain(const HapticLoopConfig& c) {
    return c.workspace.mode == WorkspaceMode::kScaling ? 1.0 : c.workspace_scale;
}

HapticLoopConfig validated(HapticLoopConfig c, const devices::DeviceProfile& profile, bool& capped) {
    if (!(std::isfinite(c.period_s) && c.period_s >= 1e-5 && c.period_s <= 0.1))
        bad("period_s", c.period_s, "must be in [1e-5, 0.1] s");
    if (!(std::isfinite(c.ewma_alpha) && c.ewma_alpha >= 0.0 && c.ewma_alpha < 1.0))
        bad("ewma_alpha", c.ewma_alpha, "must be in [0, 1)");
    if (!(std::isfinite(c.workspace_scale) && c.workspace_scale > 0.0))
        bad("workspace_scale", c.workspace_scale, "must be finite and > 0");
    check_rigid(c.device_to_world, "device_to_world");
    check_rigid(c.workpiece_pose, "workpiece_pose");
    if (c.tool.radius_m == 0.0 && c.tool.kind == ToolKind::kBall) c.tool.radius_m = c.contact.tool_radius_m;
    if (c.tool.radius_m > 0.0) validate_tool(c.tool, "HapticLoopConfig.tool");
    // The safety stage's stiffness limit: the device never renders a wall stiffer than its profile allows.
    const double cap = world_stiffness_cap_n_per_m(profile, device_gain(c));
    capped = cap_contact_stiffness(c.contact, cap);
    capped = cap_grab_stiffness(c.grab_stiffness_n_per_m, cap) || capped;
    // The scene objects felt beside the workpiece: at most `most`, each checked, each capped like the contact.
    const auto check_objects = [&](auto& objects, std::size_t most, const std::string& field) {
        if (objects.size() > most)
            throw Error("HapticLoopConfig." + field + ": " + std::to_string(objects.size()) + " objects; at most " +
                        std::to_string(most));
        for (std::size_t i = 0; i < objects.size(); ++i) {
            validate(objects[i], "HapticLoopConfig." + field + "[" + std::to_string(i) + "]");
            if (cap > 0.0 && objects[i].stiffness_n_per_m > cap) {
                objects[i].stiffness_n_per_m = cap;
                capped = true;
            }
        }
    };
    check_objects(c.elastic_objects, kMaxElasticObjects, "elastic_objects");
    check_objects(c.reference_objects, kMaxReferenceObjects, "reference_objects");
    return c;
}

}  // namespace

HapticLoop::HapticLoop(devices::HapticDevice& device, TripleBuffer<ActiveSurface>& surface,
                       SpscRing<ToolSample>& samples, HapticLoopConfig cfg)
    : HapticLoop(device, {LoopWorkpiece{&surface, &samples, cfg.sample_tap, cfg.workpiece_pose, Aabb{}}}, cfg) {}

HapticLoop::HapticLoop(devices::HapticDevice& device, const std::vector<LoopWorkpiece>& workpieces,
                       HapticLoopConfig cfg)
    : device_(device),
      cfg_(validated(cfg, device.profile(), stiffness_capped_)),
      limits_(SafetyLimits::from(device.profile(), cfg_.safety)),
      output_(output_limits(device.profile())),
      filter_(cfg_.ewma_alpha),
      torque_filter_(cfg_.ewma_alpha),
      mapper_(cfg_.workspace, cfg_.device_to_world, cfg_.workspace_scale, device.profile().workspace_m),
      watchdog_(cfg_.period_s, cfg_.safety.stale_timeout_s, cfg_.safety.stall_factor, cfg_.safety.rearm_s),
      safety_(limits_, cfg_.safety, cfg_.passivity_control),
      world_to_device_(glm::conjugate(cfg_.device_to_world.orientation)),
      period_hist_(cfg_.period_s / 50.0),
      compute_hist_(cfg_.period_s / 1000.0) {
    if (workpieces.empty() || workpieces.size() > kMaxLoopWorkpieces)
        throw Error("HapticLoop workpieces: " + std::to_string(workpieces.size()) + "; must be 1 to " +
                    std::to_string(kMaxLoopWorkpieces));
    const ToolPoints points =
        cfg_.tool_points.count > 0 ? cfg_.tool_points : ToolPoints::single(cfg_.contact.tool_radius_m);
    for (std::size_t i = 0; i < workpieces.size(); ++i) {
        const LoopWorkpiece& w = workpieces[i];
        if (!w.surface || !w.samples)
            throw Error("HapticLoop workpieces[" + std::to_string(i) + "]: no active surface or no sample ring");
        Pose pose = w.pose;
        check_rigid(pose, "workpieces[" + std::to_string(i) + "].pose");
        auto p = std::make_unique<Piece>();
        p->surface = w.surface;
        p->samples = w.samples;
        p->tap = w.sample_tap;
        p->bounds_m = w.bounds_m;
        p->world_from_model = pose;
        p->model_from_world = pose.inverse();
        p->contact = std::make_unique<MultiPointRenderer>(points, cfg_.contact, cfg_.contact_mode);
        p->cut_surface = std::make_unique<ActiveSurface>();
        start_poses_.push_back(pose);
        pieces_.push_back(std::move(p));
    }
    records_.assign(cfg_.max_ticks, TickRecord{});  // allocated and touched here, never in the loop
    pose_changes_.reserve(kMaxPoseChanges);
    base_points_ = pieces_[0]->contact->tool_points();
    tool_ = cfg_.tool;
    set_tool_op(cfg_.op, cfg_.material);
    set_symmetry(cfg_.symmetry);
    last_tool_ = mapper_.frame().tool_world;
    stiffness_cap_n_per_m_ = world_stiffness_cap_n_per_m(device.profile(), device_gain(cfg_));
    grab_ = GrabSpring(cfg_.grab_stiffness_n_per_m);
    LoopView& v = view_.back();  // before the first tick too: where the scene placed the workpieces
    v.workpiece_pose = start_poses_[0];
    std::copy(start_poses_.begin(), start_poses_.end(), v.workpiece_poses.begin());
    v.workpiece_count = static_cast<std::uint8_t>(pieces_.size());
    view_.publish();
}

HapticLoop::~HapticLoop() { stop(); }

void HapticLoop::begin_session() {
    next_change_ = 0;
    records_.resize(cfg_.max_ticks);  // back to full size after a previous stop() trimmed it
    recorded_ = 0;
    carve_gap_ = false;
    ticks_ = 0;
    overruns_ = 0;
    dropped_ = 0;
    stream_dropped_ = 0;
    tap_dropped_ = 0;
    invalid_ = 0;
    trips_ = 0;
    speed_cuts_ = 0;
    stale_remote_ = 0;
    device_lost_ = false;
    device_down_s_ = 0.0;
    realtime_ = false;
    locked_ = false;
    realtime_errno_ = 0;
    lock_errno_ = 0;
    reserved_cpu_ = -1;
    over_2ms_ = 0;
    over_5ms_ = 0;
    energy_ = 0.0;
    for (std::size_t i = 0; i < pieces_.size(); ++i) {
        Piece& p = *pieces_[i];
        p.contact->reset();
        p.cuts.clear();
        p.world_from_model = start_poses_[i];
        p.model_from_world = p.world_from_model.inverse();
        p.result = nullptr;
        p.touched = false;
        p.carve_gap = false;
    }
    target_ = 0;
    target_held_ = false;
    placing_ = false;
    placement_ = Placement{};
    pose_changes_.clear();
    pose_taken_.store(0, std::memory_order_release);
    next_pose_change_ = 0;
    PoseChange stale;
    while (pose_sets_.try_pop(stale)) {
    }  // sets made for an earlier session
    filter_.reset();
    torque_filter_.reset();
    mapper_.reset();
    watchdog_.reset();
    watchdog_.clear_trips();
    safety_.reset();
    period_hist_.clear();
    compute_hist_.clear();
    last_tool_ = mapper_.frame().tool_world;
    have_prev_now_ = false;
    prev_now_s_ = 0.0;
    prev_device_t_ = std::numeric_limits<double>::quiet_NaN();
}

void HapticLoop::start() {
    if (running()) return;
    if (thread_.joinable()) thread_.join();  // ended by itself (device lost)
    manual_session_ = false;                 // the thread takes over from step() mode
    device_.bring_up();                      // forces flow only while the loop runs (throws before any thread)
    begin_session();
    stop_requested_.store(false, std::memory_order_relaxed);
    running_.store(true, std::memory_order_release);
    thread_ = std::thread(&HapticLoop::run, this);
}

void HapticLoop::stop() {
    stop_requested_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
    if (manual_session_) {
        manual_session_ = false;
        device_.disable();  // zero force, and none until the next session
    }
    records_.resize(recorded_);  // shrinking never reallocates; start() grows it back in place
    // A device whose link went down and never came back is gone, however the session ended (a server killed
    // mid-stroke, a cable pulled): not a session that ran to its end with a device.
    if (!device_lost_.load(std::memory_order_relaxed) && ticks_.load(std::memory_order_relaxed) > 0) {
        const double down = device_.link_stats().down_for_s;
        if (down > 0.0) {
            device_down_s_ = down;
            device_lost_.store(true, std::memory_order_release);
        }
    }
}

LoopStats HapticLoop::stats() const {
    LoopStats s;
    s.ticks = ticks_.load(std::memory_order_relaxed);
    s.overruns = overruns_.load(std::memory_order_relaxed);
    s.samples_dropped = dropped_.load(std::memory_order_relaxed);
    s.records_stream_dropped = stream_dropped_.load(std::memory_order_relaxed);
    s.tap_dropped = tap_dropped_.load(std::memory_order_relaxed);
    s.invalid_samples = invalid_.load(std::memory_order_relaxed);
    s.device_lost = device_lost_.load(std::memory_order_relaxed);
    s.device_down_s = device_lost_.load(std::memory_order_acquire) ? device_down_s_ : 0.0;
    s.watchdog_trips = trips_.load(std::memory_order_relaxed);
    s.passivity_energy_j = energy_.load(std::memory_order_relaxed);
    s.realtime_scheduling = realtime_.load(std::memory_order_relaxed);
    s.memory_locked = locked_.load(std::memory_order_relaxed);
    s.realtime_errno = realtime_errno_.load(std::memory_order_relaxed);
    s.memory_lock_errno = lock_errno_.load(std::memory_order_relaxed);
    s.reserved_cpu = reserved_cpu_.load(std::memory_order_relaxed);
    s.periods_over_2ms = over_2ms_.load(std::memory_order_relaxed);
    s.periods_over_5ms = over_5ms_.load(std::memory_order_relaxed);
    s.velocity_limit_ticks = speed_cuts_.load(std::memory_order_relaxed);
    s.stale_remote_ticks = stale_remote_.load(std::memory_order_relaxed);
    s.period_histogram = period_hist_.snapshot();
    s.compute_histogram = compute_hist_.snapshot();
    return s;
}

bool HapticLoop::tick(double now_s, TickRecord& rec) {
    devices::DeviceState state;
    if (!device_.read(state)) {
        device_lost_.store(true, std::memory_order_relaxed);
        return false;
    }
    rec.t_s = now_s;
    rec.period_us = have_prev_now_ ? static_cast<float>((now_s - prev_now_s_) * 1e6) : 0.0f;
    prev_now_s_ = now_s;
    have_prev_now_ = true;
    rec.device = state;
    const MenuDetent& menu = menu_updates_.latest();
    rec.menu_open = menu.open;
    // A finite device position can still map to a non-finite world HIP (huge workspace_scale).
    const bool finite = finite_state(state) &&
                        is_finite(cfg_.device_to_world.apply(cfg_.workspace_scale * state.pose.position));
    const WatchdogStatus wd = watchdog_.update(now_s, state.t_s, finite);
    rec.watchdog = wd.causes;
    if (wd.tripped_now) trips_.store(watchdog_.trips(), std::memory_order_relaxed);
    // An invalid sample: zero force, counted, nothing pushed to the sculpt thread, no carving across it.
    const auto invalid_tick = [&] {
        device_.write(Vec3(0.0), Vec3(0.0));
        invalid_.fetch_add(1, std::memory_order_relaxed);
        safety_.hold();
        carve_gap_ = true;
        rec.hip_m = last_tool_.position;
        rec.proxy_m = last_tool_.position;
        rec.tool_world = last_tool_;
        rec.valid_sample = false;
        rec.force_enabled = false;
        rec.ramp = 0.0f;
        rec.modelling_paused = mapper_.frame().modelling_paused;
        rec.passivity_energy_j = safety_.passivity().energy_j();
        return true;
    };
    if (!finite) return invalid_tick();
    apply_tool_changes(state.t_s);
    apply_pose_changes(state.t_s);

    // Time step of the contact damping, the bubble drift and the energy books: the device's own clock,
    // else the nominal period; bounded to [period/10, 10*period] so a glitching clock cannot blow up.
    const double dt = state.t_s > prev_device_t_
                          ? std::clamp(state.t_s - prev_device_t_, 0.1 * cfg_.period_s, 10.0 * cfg_.period_s)
                          : cfg_.period_s;
    prev_device_t_ = state.t_s;

    const WorkspaceFrame& wf = mapper_.update(state, dt);
    // A finite sample can still drive the mapping non-finite (a wild sample in bubble rate control):
    // start the mapping over and treat the tick as invalid rather than carry inf into every later tick.
    if (!is_finite(wf.tool_world.position)) {
        mapper_.reset();
        reset_contact();
        return invalid_tick();
    }
    if (wf.mapping_changed || !wf.coupled) reset_contact();
    ContactOut c;
    c.proxy_m = wf.tool_world.position;
    // A device whose own contact loop runs next to it (net, local rendering) sent the tool sample that loop computed:
    // the session sculpts with its HIP and proxy, and renders no contact force itself (the device ignores it). That
    // loop's world is the workpiece's model frame (configure_net_device maps its device there).
    devices::RemoteToolSample remote;
    const bool remote_contact = device_.remote_tool(remote);
    Pose tool_world = wf.tool_world;
    const bool engaged = cfg_.engage_mask == 0 || (state.buttons & cfg_.engage_mask) != 0;
    for (const std::unique_ptr<Piece>& p : pieces_) p->result = nullptr;
    // A remote contact loop (local rendering) meets the first workpiece alone.
    target_ = remote_contact ? 0 : pick_target(wf.tool_world, target_held_);
    // Placing: the whole target workpiece follows the engaged tool rigidly; nothing is felt meanwhile.
    const bool placing = place(tool_op() == ToolOp::kPlace && engaged && wf.coupled && !wf.modelling_paused &&
                                   !menu.open && !remote_contact,
                               tool_world);
    const Pose& first_pose = pieces_[0]->world_from_model;
    if (remote_contact) {
        tool_world = first_pose * remote.tool_world;
        c.proxy_m = first_pose.apply(remote.proxy_m);
        c.contact = remote.contact;
        c.in_contact = remote.contact ? 1 : 0;
    } else if (wf.coupled && !placing) {
        c = contact(wf.tool_world, dt);
    }
    if (!c.points)
        for (const std::unique_ptr<Piece>& p : pieces_) p->touched = false;  // nothing was felt of them

    // Clamp before the filter too: a non-finite or huge contact force must not poison the filter state.
    // The world's contact force reaches the device scaled by the mapping's force_scale() (1 / s in kScaling).
    // The open menu's detent is a world force like the contact's, felt only while the tool follows the stylus.
    const double fmax = limits_.max_force_n, tmax = limits_.max_torque_nm;
    const Vec3 detent = menu.open && wf.coupled ? menu_detent_force(menu, tool_world.position) : Vec3(0.0);
    // A grab pulls the hand back to where it gripped, while it is engaged (the samples carry kGrab).
    const bool grabbing = tool_op() == ToolOp::kGrab && engaged && wf.coupled && !wf.modelling_paused && !menu.open;
    const Vec3 spring = grab_.update(grabbing && !remote_contact, c.contact, tool_world.position);
    const Vec3 world_n = mapper_.force_scale() * (c.force_n + detent + spring) + wf.force_n;
    Vec3 f = clamp_force(filter_.apply(clamp_force(world_n, fmax)), fmax);
    if (!is_finite(filter_.value())) {
        filter_.reset();
        f = Vec3(0.0);
    }
    Vec3 tau = clamp_magnitude(torque_filter_.apply(clamp_magnitude(c.torque_nm, tmax)), tmax);
    if (!is_finite(torque_filter_.value())) {
        torque_filter_.reset();
        tau = Vec3(0.0);
    }

    // The stylus position and velocity in world axes (physical, not scaled): F.dx is the work at the device.
    const Quat& r = cfg_.device_to_world.orientation;
    const SafetyOutput out =
        safety_.apply(f, tau, r * state.pose.position, r * state.velocity_m_s, state.t_s, dt, wd.force_allowed);
    if (out.over_speed) speed_cuts_.fetch_add(1, std::memory_order_relaxed);
    energy_.store(safety_.passivity().energy_j(), std::memory_order_relaxed);
    // What the device can render: 3-DOF drops torque, 5-DOF the roll axis; per-axis limits.
    const Wrench to_device = map_to_device(Wrench{out.force_n, out.torque_nm}, world_to_device_, output_);
    device_.write(to_device.force_n, to_device.torque_nm);
    safety_.sent(r * to_device.force_n);  // the passivity books take what the device got (per-axis limits)

    const bool hold = wf.modelling_paused || menu.open || carve_gap_ || !wd.force_allowed || out.over_speed ||
                      !engaged || placing || (remote_contact && (remote.hold || remote.stale));
    push_sample(state, tool_world, c, hold, !wd.force_allowed || out.over_speed || placing, rec);

    last_tool_ = tool_world;
    rec.hip_m = tool_world.position;
    rec.proxy_m = c.proxy_m;
    // The force the device got; a stale remote sample's is an earlier tick's, logged as such.
    rec.force_n = remote_contact ? first_pose.rotate(remote.force_n) : out.force_n;
    rec.remote_stale = remote_contact && remote.stale;
    if (rec.remote_stale) stale_remote_.fetch_add(1, std::memory_order_relaxed);
    rec.contact = c.contact;
    rec.hip_inside = c.hip_inside;
    rec.object_force_n = c.object_force_n;
    rec.points_in_contact = c.in_contact;
    if (c.points) {
        for (int k = 0; k < 2 && k < c.points->points; ++k) {
            const PointState& p = c.points->point[k];  // in that workpiece's model frame
            const Pose& wp = *c.points_pose;
            PointRecord& pr = rec.points[k];
            pr.world_m = wp.apply(p.world_m);
            pr.proxy_m = wp.apply(p.proxy_m);
            pr.force_n = wp.rotate(p.force_n);
            pr.depth_m = p.contact ? p.depth_m : 0.0;
            const Vec3 an = glm::abs(p.normal);  // the ray sets are the model's axes
            pr.collision_id = !p.contact ? -1 : (an.x >= an.y && an.x >= an.z ? 0 : (an.y >= an.z ? 1 : 2));
        }
    }
    rec.tool_world = tool_world;
    rec.torque_nm = out.torque_nm;
    rec.modelling_paused = wf.modelling_paused;
    rec.force_enabled = out.enabled;
    rec.ramp = static_cast<float>(out.ramp);
    rec.passivity_energy_j = safety_.passivity().energy_j();
    return true;
}

void HapticLoop::finish(TickRecord& rec, double compute_s) {
    rec.compute_us = static_cast<float>(compute_s * 1e6);
    // The session's first tick has no period.
    if (ticks_.load(std::memory_order_relaxed) > 0) {
        period_hist_.add(static_cast<double>(rec.period_us) * 1e-6);
        if (rec.period_us > 2000.0f) over_2ms_.fetch_add(1, std::memory_order_relaxed);
        if (rec.period_us > 5000.0f) over_5ms_.fetch_add(1, std::memory_order_relaxed);
    }
    compute_hist_.add(compute_s);
    if (recorded_ < records_.size()) records_[recorded_++] = rec;
    if (cfg_.record_stream && !cfg_.record_stream->try_push(rec)) stream_dropped_.fetch_add(1, std::memory_order_relaxed);
    const std::size_t n = ticks_.fetch_add(1, std::memory_order_relaxed) + 1;

    const WorkspaceFrame& wf = mapper_.frame();
    LoopView& v = view_.back();
    v.tick = n;
    v.t_s = rec.t_s;
    v.device_t_s = rec.device.t_s;
    v.tool_world = rec.tool_world;
    v.force_n = rec.force_n;
    v.contact = rec.contact;
    v.modelling_paused = rec.modelling_paused;
    v.buttons = rec.device.buttons;
    v.joystick_y = rec.device.joystick_y;
    v.box = wf.box;
    v.box_half_extents_m = wf.box_half_extents_m;
    v.bubble_centre_m = wf.bubble_centre_m;
    v.bubble_radius_m = wf.bubble_radius_m;
    v.proxy_m = rec.proxy_m;
    v.points_in_contact = rec.points_in_contact;
    v.tool = tool_;
    v.menu_open = rec.menu_open;
    v.workpiece_pose = pieces_[0]->world_from_model;
    for (std::size_t i = 0; i < pieces_.size(); ++i) v.workpiece_poses[i] = pieces_[i]->world_from_model;
    v.workpiece_count = static_cast<std::uint8_t>(pieces_.size());
    v.target_workpiece = static_cast<std::uint8_t>(target_);
    v.placement = placement_;
    v.placing = placing_;
    v.samples = pieces_[0]->pushed;
    view_.publish();
}

TickRecord HapticLoop::step(double loop_time_s) {
    if (running()) throw Error("HapticLoop::step: the loop thread is running; stop() it before stepping");
    if (!manual_session_) {
        if (thread_.joinable()) thread_.join();
        device_.bring_up();
        begin_session();
        manual_session_ = true;
    }
    TickRecord rec;
    const std::int64_t start = monotonic_ns();
    bool ok = false;
    try {
        ok = tick(loop_time_s, rec);
    } catch (...) {
        device_lost_.store(true, std::memory_order_relaxed);
    }
    if (!ok) {
        try {
            device_.write(Vec3(0.0), Vec3(0.0));
        } catch (...) {
        }
        TickRecord lost;
        lost.t_s = loop_time_s;
        lost.hip_m = last_tool_.position;
        lost.proxy_m = last_tool_.position;
        lost.tool_world = last_tool_;
        lost.valid_sample = false;
        lost.force_enabled = false;
        lost.ramp = 0.0f;
        return lost;
    }
    finish(rec, static_cast<double>(monotonic_ns() - start) * 1e-9);
    return rec;
}

void HapticLoop::run() noexcept {
    prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);  // wake within ~1 ns of the deadline, not the 50 us default
    name_this_thread("tridex-haptics");
    if (cfg_.free_run) {
        try {
            run_free();
        } catch (...) {
            device_lost_.store(true, std::memory_order_relaxed);  // as below: a failed driver is a lost device
        }
        device_.disable();
        running_.store(false, std::memory_order_release);
        return;
    }
    if (cfg_.request_realtime) {
        const RealtimeStatus rt = request_realtime(cfg_.realtime_priority, cfg_.lock_memory);
        realtime_.store(rt.fifo, std::memory_order_relaxed);
        locked_.store(rt.memory_locked, std::memory_order_relaxed);
        realtime_errno_.store(rt.fifo_errno, std::memory_order_relaxed);
        lock_errno_.store(rt.lock_errno, std::memory_order_relaxed);
        if (rt.fifo && cfg_.reserve_cpu) reserved_cpu_.store(reserve_cpu_for_this_thread(), std::memory_order_relaxed);
    }
    prefault_stack();  // the ticks' stack pages resident (and locked) before the first deadline
    const std::int64_t period_ns = std::llround(cfg_.period_s * 1e9);
    const std::int64_t t0 = monotonic_ns();
    std::int64_t next = t0;
    try {
        while (!stop_requested_.load(std::memory_order_acquire)) {
            sleep_until_ns(next);
            const std::int64_t start = monotonic_ns();
            TickRecord rec;
            if (!tick(static_cast<double>(start - t0) * 1e-9, rec)) break;  // device lost
            const std::int64_t end = monotonic_ns();
            finish(rec, static_cast<double>(end - start) * 1e-9);
            next += period_ns;
            if (end >= next) {  // missed the next deadline: count it and skip the deadlines already past
                overruns_.fetch_add(1, std::memory_order_relaxed);
                next += ((end - next) / period_ns + 1) * period_ns;
            }
        }
    } catch (...) {
        // A device driver failed: treat it as a lost device (the zero-force write below still runs).
        device_lost_.store(true, std::memory_order_relaxed);
    }
    device_.disable();  // zero force, and none until the next start()
    release_reserved_cpu();
    running_.store(false, std::memory_order_release);
}

void HapticLoop::run_free() {
    for (std::uint64_t n = 0; !stop_requested_.load(std::memory_order_acquire); ++n) {
        const std::int64_t start = monotonic_ns();
        TickRecord rec;
        if (!tick(static_cast<double>(n) * cfg_.period_s, rec)) break;  // the replay's end
        finish(rec, static_cast<double>(monotonic_ns() - start) * 1e-9);
    }
}

}  // namespace tridex::haptics
