// haptics/haptic_loop.hpp - the 1 kHz haptic thread: device -> workspace map -> contact -> filter
// -> safety (clamps, watchdog, ramp, passivity) -> device, with telemetry.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include "core/active_surface.hpp"
#include "core/pose.hpp"
#include "core/sequenced_sample.hpp"
#include "core/spsc_ring.hpp"
#include "core/tool_sample.hpp"
#include "core/tool_shape.hpp"
#include "core/triple_buffer.hpp"
#include "devices/haptic_device.hpp"
#include "haptics/elastic_object.hpp"
#include "haptics/ewma_filter.hpp"
#include "haptics/god_object.hpp"
#include "haptics/grab_spring.hpp"
#include "haptics/menu_detent.hpp"
#include "haptics/multipoint.hpp"
#include "haptics/recent_cuts.hpp"
#include "haptics/reference_object.hpp"
#include "haptics/wrench_output.hpp"
#include "haptics/safety.hpp"
#include "haptics/safety_limits.hpp"
#include "haptics/telemetry.hpp"
#include "haptics/watchdog.hpp"
#include "haptics/workspace_mapping.hpp"

namespace tridex::haptics {

/// A change of the Boolean, material or tool that a replay applies at a given device time (the recorded tick's
/// device time), so the samples carry exactly what the recorded session's samples carried.
struct ToolChange {
    double device_t_s = 0.0;        ///< applied at the first valid device sample with t_s >= this, s
    ToolOp op = ToolOp::kSubtract;  ///< the Boolean from then on
    std::uint8_t material = 0;      ///< the material from then on
    ToolShape tool{};               ///< the tool from then on (HapticLoop::set_tool's rules); radius_m 0 = unchanged
    Symmetry symmetry{};            ///< the symmetry from then on
    /// The workpiece the samples carve from then on (HapticLoop::choose_workpiece), taken at once even within a
    /// stroke, so a replay carves the workpiece each recorded tick carved; -1 = unchanged.
    int workpiece = -1;
};

/// Most workpieces one haptic loop feels and sculpts.
inline constexpr std::size_t kMaxLoopWorkpieces = 8;

/// A workpiece's pose set on a tick: the undo or redo of a placement (HapticLoop::set_workpiece_pose), or a replay's
/// repetition of one (HapticLoopConfig::pose_schedule).
struct PoseChange {
    /// The session's tick (0-based, as its TickRecords count) that took it: a replay, whose ticks are the recorded
    /// ones, takes it at the first tick from this one on with a finite sample on which the tool holds no workpiece.
    std::uint64_t tick = 0;
    double device_t_s = 0.0;     ///< that tick's device time, s (for people reading a recording)
    std::uint8_t workpiece = 0;  ///< the workpiece, in the loop's order
    Pose pose{};                 ///< its model frame -> the world from then on (m, unit quaternion)
};

/// A placement that ended: the tool let go of the workpiece it held with ToolOp::kPlace (LoopView::placement).
struct Placement {
    std::uint64_t serial = 0;      ///< 1, 2, ... per placement ended; 0 = none yet
    std::uint8_t workpiece = 0;    ///< the workpiece it moved, in the loop's order
    Pose before{};                 ///< its pose at the grip
    Pose after{};                  ///< its pose at the release
    std::uint64_t at_samples = 0;  ///< samples its sculpt ring had taken at the release (the sculpt threads' clock)
};

/// One workpiece the haptic loop feels and sculpts: where it reads the workpiece's active surface (in the workpiece's
/// model frame), where it hands the workpiece's sculpt thread its tool samples (model frame), where it also taps them
/// for the workpiece's journal, its pose, and its lattice's box for choosing the nearest workpiece.
struct LoopWorkpiece {
    TripleBuffer<ActiveSurface>* surface = nullptr;  ///< the loop is its only reader; must outlive the loop
    SpscRing<ToolSample>* samples = nullptr;         ///< the loop is its only producer; must outlive the loop
    /// As HapticLoopConfig::sample_tap, for this workpiece's samples; nullptr = none.
    SpscRing<SequencedSample>* sample_tap = nullptr;
    Pose pose{};       ///< its model frame -> the world (m, unit quaternion)
    Aabb bounds_m{};   ///< its lattice's box in its model frame, m; empty = never the nearest
};

/// Settings of the haptic loop (SI units).
struct TickRecord;

struct HapticLoopConfig {
    double period_s = 1e-3;        ///< tick period, s (1 kHz), in [1e-5, 0.1]
    ContactParams contact;         ///< god-object stiffness, damping, tool radius
    double ewma_alpha = 0.9;       ///< force filter weight a, [0, 1) (Peng et al.)
    Pose device_to_world;          ///< device frame -> world frame (unit quaternion): the initial workspace mapping
    /// The workpiece's pose: its model frame (where its lattice, active surface and every ToolSample live) -> the
    /// world (m, unit quaternion). The contact with the workpiece runs in the model frame and its force and torque
    /// are turned back into the world; the scene objects, the workspace, the menu and every TickRecord stay in the
    /// world. Identity (the default): the model frame is the world.
    Pose workpiece_pose{};
    double workspace_scale = 1.0;  ///< s > 0: world = R * (s * p) + offset, offset = device_to_world.position until the
                                   ///< workspace technique moves it (WorkspaceMapper); kScaling's fixed gain, which also
                                   ///< divides the world's contact force on its way to the device (force_scale())
    /// The tool carried by every ToolSample (what the sculpt thread sweeps). A ball of radius 0 (the default)
    /// = a ball of contact.tool_radius_m. The contact points (tool_points) should cover this tool's surface
    /// (haptics::tool_points_for) so that touch and cut agree.
    ToolShape tool{};
    ToolOp op = ToolOp::kSubtract; ///< Boolean carried by every ToolSample
    std::uint8_t material = 0;     ///< material id carried by every ToolSample (what kUnion adds, kPaint sets)
    /// Symmetry carried by every ToolSample (the sculpt thread applies the symmetric copies; the contact, and so the
    /// force, stays the person's own tool's: ghost contacts would pull the hand toward places it is not).
    Symmetry symmetry{};
    /// Button bits (DeviceState::buttons) that engage the tool: nonzero = the samples carry op only while one of
    /// them is held, kNone otherwise (the desk mouse's left button); 0 = always engaged.
    std::uint32_t engage_mask = 0;
    std::size_t max_ticks = 0;     ///< TickRecords preallocated (recording stops when full); 0 = none
    /// Where every tick's record is also pushed, without waiting (a full ring drops it, counted in
    /// LoopStats::records_stream_dropped), for a consumer that streams a recording of any length to disk; nullptr =
    /// none. The ring must outlive the loop's run.
    SpscRing<TickRecord>* record_stream = nullptr;
    /// Where every ToolSample the sculpt ring took is also pushed, numbered (SequencedSample), without waiting (a
    /// full tap drops it, counted in LoopStats::tap_dropped): the session journal's intake thread, which keeps what
    /// the sculpt thread has not applied yet; nullptr = none. The ring must outlive the loop's run.
    SpscRing<SequencedSample>* sample_tap = nullptr;
    /// A fault injected on purpose (the chaos tests, docs/benchmarks/chaos.md): right after the sculpt ring took its
    /// sample number fault_kill_at_sample (1, 2, ...; counted since the loop was made), the loop kills its own process
    /// with SIGKILL, so a test knows exactly how many samples the session had made. 0 = never.
    std::uint64_t fault_kill_at_sample = 0;
    WorkspaceConfig workspace;     ///< workspace technique (WorkspaceMode) and its parameters
    SafetyConfig safety;           ///< velocity limit, ramp-in, watchdog and passivity-controller settings
    bool passivity_control = false;///< the passivity controller damps energy the environment creates (the observer always runs)
    bool request_realtime = true;  ///< ask for SCHED_FIFO (and mlockall) for the loop thread; refusals are reported, not fatal
    int realtime_priority = 80;    ///< SCHED_FIFO priority asked for (clamped to the system's range)
    bool lock_memory = true;       ///< with request_realtime: mlockall(MCL_CURRENT | MCL_ONFAULT) (see request_realtime())
    /// Once SCHED_FIFO is granted: set a CPU aside for the loop thread (core/cpu_reservation.hpp), so that the
    /// threads kept off it (the presenting thread) cannot delay its start with a long system call.
    bool reserve_cpu = true;
    /// Contact points on the tool (tool frame). count 0 (default) = one point at the tool centre with
    /// radius contact.tool_radius_m, i.e. the single god-object. Singapogu ch. 3: P_i = R*T_i + P_w.
    ToolPoints tool_points{};
    /// Per-point god-objects (thesis) or the haptic interaction mesh (Popescu et al. 3.1-3.2).
    MultiPointMode contact_mode = MultiPointMode::kIndependentProxies;
    /// Changes applied at device times (a replay of a session whose keys changed the op or the tool size), in
    /// increasing device_t_s; empty for live sessions.
    std::vector<ToolChange> tool_schedule{};
    /// A replay's pose sets (the session's PoseChange list, tick never decreasing, each workpiece in range, each pose
    /// finite and unit: checked where the recording is read), each taken at the first tick from PoseChange::tick on
    /// with a finite sample on which the tool holds no workpiece, as the session took it.
    std::vector<PoseChange> pose_schedule{};
    /// Free running, for a replay that draws no window (nothing waits on its pace): ticks run back to back without
    /// sleeping, the loop clock is tick index x period_s (each tick on time, as the recorded loop meant them), the loop
    /// stays at most kFreeRunLead samples ahead of the sculpt thread (so the sculpt thread gets every sample and the
    /// active surface the contact reads is about as recent as in a paced session that keeps up), and no real-time
    /// scheduling or CPU is asked for. The samples, and so the model, are those of the paced loop; only the wall time
    /// differs. Never for a live device: the loop then waits on the sculpt thread.
    bool free_run = false;
    /// Elastic (or rigid) spheres felt beside the workpiece, at most kMaxElasticObjects: each adds
    /// elastic_force() of the tool's contact points against its undeformed sphere (Popescu, Burdea, Bouzit 3.3) to
    /// the contact force. Their stiffness is capped like the contact's (the device profile's max stiffness).
    std::vector<ElasticSphere> elastic_objects{};
    /// Rigid reference objects felt beside the workpiece (closed meshes placed in the scene, never sculpted), at most
    /// kMaxReferenceObjects: each adds penetration_force() of the tool's contact points against its distance field
    /// (reference_contacts) to the contact force. Their stiffness is capped like the contact's.
    std::vector<ReferenceObject> reference_objects{};
    /// Stiffness of the spring a grab (ToolOp::kGrab) pulls the hand back to its anchor with (GrabSpring), N/m
    /// (world), finite and >= 0 (0: none); capped like the contact's (the device profile's max stiffness).
    double grab_stiffness_n_per_m = kGrabStiffnessNPerM;
};

/// Samples a free-running loop (HapticLoopConfig::free_run) may have in the ring, not yet taken by the sculpt thread.
inline constexpr std::size_t kFreeRunLead = 16;

/// Most elastic objects a haptic loop feels (HapticLoopConfig::elastic_objects).
inline constexpr std::size_t kMaxElasticObjects = 16;

/// Most reference objects a haptic loop feels (HapticLoopConfig::reference_objects).
inline constexpr std::size_t kMaxReferenceObjects = 8;

/// One contact point's state in a tick (world frame, SI units), for recordings.
struct PointRecord {
    Vec3 world_m{0.0};              ///< the point on the tool, m
    Vec3 proxy_m{0.0};              ///< its god-object (collision point), m; = world_m when free
    Vec3 force_n{0.0};              ///< its force before filtering and limits, N
    double depth_m = 0.0;           ///< penetration (deviation), m; 0 when free
    std::int32_t collision_id = -1; ///< ray set (0 = X, 1 = Y, 2 = Z) best aligned with the contact normal; -1 = free
};

/// What one tick did (world frame), for telemetry and tests.
struct TickRecord {
    double t_s = 0.0;          ///< tick start on the loop clock, s since start() (step(): the time given)
    Vec3 hip_m{0.0};           ///< HIP (tool centre) in the world, m; the last valid HIP on an invalid sample
    Vec3 proxy_m{0.0};         ///< god-object position, m
    Vec3 force_n{0.0};         ///< force sent to the device (after filter and the safety stage), world frame, N
    bool contact = false;      ///< the contact stage (god-object) was in contact
    bool hip_inside = false;   ///< point 0 (the HIP for a ball) lay inside material by the snapshot
    /// The scene objects' part of the contact force (HapticLoopConfig::elastic_objects, against their undeformed
    /// spheres, and reference_objects, against their distance fields), world frame, N, before the workspace mapping's force scale, the filter and the safety stage; 0 when
    /// the tool touches none.
    Vec3 object_force_n{0.0};
    float period_us = 0.0f;    ///< time since the previous tick's start, us (0 on the first tick)
    float compute_us = 0.0f;   ///< time from this tick's start to the end of its work, us
    bool valid_sample = true;  ///< false when the device sample had a non-finite value (zero force sent)
    devices::DeviceState device;     ///< the raw device sample of this tick, device frame (as read, even when invalid)
    Pose tool_world;                 ///< tool pose in the world (position = hip_m); the last valid one on an invalid sample
    Vec3 torque_nm{0.0};             ///< torque sent to the device, world frame, N*m
    bool modelling_paused = false;   ///< the workspace mapper paused modelling (ToolSample op = kNone)
    std::uint8_t watchdog = 0;       ///< WatchdogCause bits found this tick (0 = healthy sample)
    bool force_enabled = true;       ///< false when the watchdog or the velocity limit held the output at zero
    float ramp = 1.0f;               ///< ramp-in factor applied to force and torque, [0, 1]
    double passivity_energy_j = 0.0; ///< passivity observer energy E after this tick, J (< 0: energy created)
    /// The first two contact points (the wand's top and bottom, Singapogu Table 3; point 0 alone for a
    /// single-point tool), world frame.
    std::array<PointRecord, 2> points{};
    int points_in_contact = 0;       ///< contact points touching material this tick
    /// The Boolean selected this tick (before engagement and pauses; kNone on an invalid sample).
    ToolOp op = ToolOp::kNone;
    std::uint8_t material = 0;       ///< the material selected this tick
    Symmetry symmetry{};             ///< the symmetry the tick's sample carried (core/symmetry.hpp)
    ToolShape tool{};                ///< the tool this tick's sample carries (radius_m 0 on an invalid sample)
    /// Local rendering (a device's remote tool sample): the sample was an earlier tick's (RemoteToolSample::stale),
    /// so force_n is the last force its loop rendered, not one the device got on this tick.
    bool remote_stale = false;
    /// The pie menu was open (HapticLoop::set_menu): the tick's sample carried ToolOp::kNone, and force_n includes the
    /// detent (while the tool followed the stylus).
    bool menu_open = false;
    /// The workpiece the tick's sample carved (or placed): the others got the tick's sample with ToolOp::kNone.
    std::uint8_t workpiece = 0;
};

/// Counters of the loop; readable while it runs.
struct LoopStats {
    std::size_t ticks = 0;            ///< ticks that got a sample from the device
    std::size_t overruns = 0;         ///< ticks that ended after the next deadline (missed deadlines skipped)
    std::size_t samples_dropped = 0;  ///< ToolSamples not pushed because the ring was full
    std::size_t records_stream_dropped = 0;  ///< TickRecords not pushed to HapticLoopConfig::record_stream (ring full)
    std::size_t tap_dropped = 0;      ///< samples not pushed to HapticLoopConfig::sample_tap (ring full)
    std::size_t invalid_samples = 0;  ///< device samples with a non-finite value (zero force sent)
    bool device_lost = false;         ///< device.read() returned false (or threw) and the loop ended, or the loop
                                      ///< was stopped while the device's link was down (DeviceLinkStats::down_for_s)
    double device_down_s = 0.0;       ///< that link had been down this long when the loop stopped, s (else 0)
    std::size_t watchdog_trips = 0;   ///< watchdog trip episodes (non-finite, stale or stalled data)
    double passivity_energy_j = 0.0;  ///< passivity observer energy E, J (< 0: the environment created energy)
    bool realtime_scheduling = false; ///< the loop thread got SCHED_FIFO (false when refused or not asked)
    bool memory_locked = false;       ///< mlockall succeeded for the loop
    int realtime_errno = 0;           ///< why SCHED_FIFO was refused (RealtimeStatus::fifo_errno: EPERM, ...); 0 = granted or not asked
    int memory_lock_errno = 0;        ///< why mlockall was refused (RealtimeStatus::lock_errno); 0 = locked or not asked
    int reserved_cpu = -1;  ///< the CPU set aside for the loop thread (HapticLoopConfig::reserve_cpu); -1 = none
    std::size_t periods_over_2ms = 0; ///< tick periods longer than 2 ms (stalls a hand feels as a step in the force)
    std::size_t periods_over_5ms = 0; ///< tick periods longer than 5 ms
    std::size_t velocity_limit_ticks = 0;  ///< ticks whose output was cut by the velocity limit
    std::size_t stale_remote_ticks = 0;    ///< local rendering: ticks whose remote tool sample was stale
    Histogram period_histogram;       ///< tick periods, s: bins of period_s / 50 up to 4 periods, then overflow
    Histogram compute_histogram;      ///< tick compute times, s: bins of period_s / 1000 up to 0.2 periods
};

/// What the render thread needs from the haptic loop, published every tick (world frame, SI units).
struct LoopView {
    std::uint64_t tick = 0;         ///< ticks so far when published; 0 = nothing yet
    double t_s = 0.0;               ///< loop time of the tick, s
    /// The device's time of the tick's sample, s (DeviceState::t_s: the clock of the samples, the journal and a
    /// recording; it falls behind t_s when the loop skips missed deadlines), as the device gave it: a tick with an invalid
    /// sample may carry a non-finite time.
    double device_t_s = 0.0;
    Pose tool_world;                ///< tool pose, m
    Vec3 force_n{0.0};              ///< force sent, N
    bool contact = false;           ///< the tool touches material
    bool modelling_paused = false;  ///< workspace button held (draw the transparent box)
    std::uint32_t buttons = 0;      ///< the device's button bits on that tick (DeviceState::buttons)
    Pose box;                       ///< workspace box centre (m) and orientation
    Vec3 box_half_extents_m{0.0};   ///< its half extents, m
    Vec3 bubble_centre_m{0.0};      ///< bubble centre, m (bubble mode)
    double bubble_radius_m = 0.0;   ///< bubble radius, m; 0 when not in bubble mode
    /// The proxy (god-object of contact point 0, Peng et al.: held on the surface while the HIP goes
    /// inside), world m; the tool centre when free.
    Vec3 proxy_m{0.0};
    int points_in_contact = 0;      ///< contact points touching material this tick
    ToolShape tool{};               ///< the tool in use (HapticLoop::set_tool)
    bool menu_open = false;         ///< the loop feels the pie menu (HapticLoop::set_menu) on that tick
    double joystick_y = 0.0;        ///< the device's joystick on that tick (DeviceState::joystick_y)
    /// The workpiece's pose on that tick (its model frame -> the world): HapticLoopConfig::workpiece_pose until the
    /// tool places it (ToolOp::kPlace). Views draw and pick the workpiece through it. With several workpieces, the
    /// first one's (workpiece_poses[0]).
    Pose workpiece_pose{};
    /// Every workpiece's pose on that tick, in the loop's order (the first workpiece_count are set).
    std::array<Pose, kMaxLoopWorkpieces> workpiece_poses{};
    std::uint8_t workpiece_count = 1;  ///< workpieces the loop feels
    std::uint8_t target_workpiece = 0; ///< the workpiece the tool carves (or places) now
    Placement placement{};             ///< the newest placement that ended (serial 0: none yet)
    bool placing = false;              ///< the tool holds a workpiece (ToolOp::kPlace, engaged) on that tick
    std::uint64_t samples = 0;         ///< samples the first workpiece's sculpt ring has taken (the sculpt clock)
};

/// The 1 kHz haptic thread (DESIGN.md, "three threads"). It ticks on absolute deadlines
/// (clock_nanosleep with TIMER_ABSTIME on CLOCK_MONOTONIC, the thread's timer slack set to 1 ns), asks
/// for SCHED_FIFO and mlockall at start (request_realtime; refusals are reported in LoopStats), and
/// measures its own period and compute time (per tick and in fixed-bin histograms). Each tick:
///   device.read() -> validate (a non-finite time, pose or velocity sends zero force and is counted)
///   -> Watchdog (non-finite, stale or stalled data -> zero output, re-arm, ramp in again)
///   -> WorkspaceMapper (tool pose in the world, modelling paused, box/bubble; a workspace jump or a
///   declutch resets the contact) -> contact() on the newest ActiveSurface (TripleBuffer::latest), less the
///   loop's own carving sweeps it does not hold yet (RecentCuts: while carving it lags the tool by tens of ms):
///   the MultiPointRenderer (one god-object per tool point, force sum and torque about the tool centre,
///   or the interaction mesh), whose damping dt is the step of the device's clock, t_s, or period_s when
///   that does not advance -> + the open menu's detent (set_menu) -> x the mapper's force_scale() (1 / s in
///   kScaling) + its force (bubble wall)
///   -> clamp -> EwmaFilter (reset when non-finite) -> clamp to the profile's max force (torque: its own filter and max torque)
///   -> SafetyStage (clamps, velocity limit and watchdog gate, ramp-in, passivity controller when
///   enabled, passivity observer) -> map_to_device (the device's DOF and per-axis limits: 3-DOF
///   drops torque, 5-DOF the roll axis) -> device.write(R^-1 * F_world, R^-1 * tau_world)
///   -> push a ToolSample (device time, HIP, tool orientation, radius, op, or kNone while modelling is
///   paused or the menu is open, buttons) to the ring (when full, count a drop and go on: the next successful
///   push just makes a longer segment; after a dropped kNone sample the next one is kNone too, so no sweep
///   starts from before a pause) -> store a TickRecord into the preallocated array (until it is full)
///   -> publish a LoopView for the renderer.
/// A device whose contact loop runs next to it (device.remote_tool(): the net driver in local haptic rendering,
/// Popescu, Burdea, Bouzit section 2) replaces contact(): the HIP, proxy and hold of its tool sample go into the
/// ToolSample and the TickRecord (with the force it rendered), and the session renders no contact force itself.
/// Inside the loop nothing allocates, locks or waits on another thread. When device.read() returns
/// false (or read/write throws), the loop writes zero force and ends by itself (device_lost). On every
/// exit it writes zero force last. The loop is the only reader of `surface`, the only producer of
/// `samples` and the only user of `device` while it runs; all three must outlive it.
/// Several workpieces (LoopWorkpiece): the contact runs against each one's active surface in its own model frame and
/// the forces and torques add up (each has its own god-objects and recent cuts); each tick's sample goes to every
/// workpiece in its model frame, carrying the operation only for the target workpiece (the others get kNone, so
/// their active surfaces follow the tool and no stroke of theirs stays open). The target is the chosen one
/// (choose_workpiece, a replay's schedule), else the one the tool touched on the previous tick (the current target
/// first), else the one whose box is nearest; it does not change while the tool carves it where it touches it, nor
/// while it places (ToolOp::kPlace moves the target alone).
class HapticLoop {
public:
    /// Checks the configuration; throws tridex::Error naming the field at fault (HapticLoopConfig.*,
    /// ContactParams.*, WorkspaceConfig.*, SafetyConfig.*, or the device profile's max_force_n /
    /// max_torque_nm). Preallocates (and touches) cfg.max_ticks TickRecords.
    HapticLoop(devices::HapticDevice& device, TripleBuffer<ActiveSurface>& surface, SpscRing<ToolSample>& samples,
               HapticLoopConfig cfg);
    /// Several workpieces (1..kMaxLoopWorkpieces; cfg.workpiece_pose and cfg.sample_tap are ignored: each
    /// LoopWorkpiece has its own). Throws tridex::Error as the constructor above, "HapticLoop workpieces: ..." for
    /// none, too many or a missing surface or ring, and "HapticLoopConfig.workpieces[i].pose...: ..." for a pose that
    /// is not rigid.
    HapticLoop(devices::HapticDevice& device, const std::vector<LoopWorkpiece>& workpieces, HapticLoopConfig cfg);
    /// Stops the thread if it runs.
    ~HapticLoop();
    HapticLoop(const HapticLoop&) = delete;
    HapticLoop& operator=(const HapticLoop&) = delete;

    /// Starts the thread; a second call while it runs does nothing. Every start begins a session: it
    /// clears the records, counters and histograms, the filters, the god-object, the workspace mapping
    /// (back to device_to_world), the watchdog, the ramp (which restarts) and the passivity books.
    /// Brings the device up first (HapticDevice::bring_up: whatever of open, home and enable is still due),
    /// so forces reach it only while the loop runs; throws tridex::Error (no thread started) when it cannot.
    void start();
    /// Asks the thread to finish its tick, send zero force and exit, then joins; ends a step() session
    /// with a zero-force write. The device is disabled (HapticDevice::disable) when the loop ends, by stop()
    /// or by itself. Idempotent.
    void stop();
    /// True from start() until the thread has exited (after stop(), or by itself on device loss).
    bool running() const { return running_.load(std::memory_order_acquire); }
    /// One record per tick, in order (at most max_ticks). Valid only after stop().
    const std::vector<TickRecord>& records() const { return records_; }
    /// The counters so far (each is read atomically; the set is not one snapshot while running).
    LoopStats stats() const;
    /// The configuration.
    const HapticLoopConfig& config() const { return cfg_; }
    /// True when the contact stiffness (or a material's) was cut at construction to the device profile's
    /// max_stiffness_n_per_m under the workspace gain (world_stiffness_cap_n_per_m); config() holds the cut values.
    bool stiffness_capped() const { return stiffness_capped_; }

    /// Deterministic stepping: runs one tick on the calling thread with loop_time_s (s, increasing) as
    /// the loop clock instead of CLOCK_MONOTONIC, for tests and offline replays driven by simulated
    /// time. The first step() after construction or stop() starts a session exactly as start() does
    /// (bringing the device up; no real-time request). Returns the tick's record (also stored in records(), whose unfilled
    /// tail is default records until stop()). When the device is lost it writes zero force, sets
    /// stats().device_lost and returns a record with valid_sample = false. stop() ends the session
    /// and writes zero force. Throws tridex::Error when the loop thread is running.
    TickRecord step(double loop_time_s);
    /// Changes the Boolean and material the following ToolSamples carry (any thread, lock-free; the sculpt thread
    /// closes the stroke at the change). Starts as cfg.op / cfg.material; start() keeps the last value set.
    void set_tool_op(ToolOp op, std::uint8_t material);
    /// Changes the symmetry the following ToolSamples carry (any thread, lock-free; the sculpt thread closes the
    /// stroke at the change). Starts as cfg.symmetry. Throws tridex::Error when !valid_symmetry(s).
    void set_symmetry(const Symmetry& s);
    /// The symmetry the samples carry now (any thread).
    Symmetry symmetry() const { return symmetry_from_bits(symmetry_.load(std::memory_order_relaxed)); }
    /// The Boolean the samples carry now (any thread).
    ToolOp tool_op() const { return static_cast<ToolOp>(op_.load(std::memory_order_relaxed) & 0xffu); }
    /// The material the samples carry now (any thread).
    std::uint8_t tool_material() const { return static_cast<std::uint8_t>(op_.load(std::memory_order_relaxed) >> 8); }
    /// Changes the tool the following ToolSamples carry to `tool`, the configured tool at another size: the
    /// same kind (ball or flat end; a mesh tool keeps its size), radius_m (and length_m) finite and > 0. The
    /// contact points are the configured ones scaled by tool.radius_m / config().tool.radius_m, so touch and
    /// cut still agree. One writer thread (the window's); lock-free: the loop takes it at its next valid tick
    /// (and resets the contact). Returns false, changing nothing, for another kind, a mesh tool or a bad size.
    bool set_tool(const ToolShape& tool);
    /// Opens, moves or closes the in-scene pie menu (world frame, SI). One writer thread (the render thread);
    /// lock-free: the loop takes the newest menu at its next tick, and start() keeps the last one set. While
    /// m.open, every ToolSample carries ToolOp::kNone (no carving, as while modelling is paused) and, while the
    /// tool follows the stylus, menu_detent_force(m, HIP) is added to the contact force before the mapping's
    /// force_scale(), the filter, the clamps and the safety stage (a world force, bounded like the contact's); the
    /// workpiece is still felt. Closing resumes carving on the next tick; the first carving sweep starts at the
    /// previous tick's sample (the last menu sample; when that one was dropped, the first sample after is kNone).
    /// Throws tridex::Error (publishing nothing) when m.open and check_menu_detent(m, the world stiffness cap
    /// of the device profile under the workspace gain) fails; a closed menu is always taken.
    void set_menu(const MenuDetent& m);
    /// The newest LoopView (render thread; exactly one reader thread). Before the first tick: a default LoopView
    /// (tick 0) with the configured workpiece_pose.
    const LoopView& latest_view() { return view_.latest(); }
    /// Chooses the workpiece the tool carves from the next tick on: 0..workpieces()-1, or -1 for the automatic
    /// choice (touched, else nearest). Any thread, lock-free; the loop takes it when the tool is not carving or
    /// placing. Returns false, changing nothing, for an index out of range.
    bool choose_workpiece(int index);
    /// The chosen workpiece (-1: automatic).
    int chosen_workpiece() const { return chosen_.load(std::memory_order_relaxed); }
    /// Sets workpiece `index`'s pose (model frame -> world, m, unit quaternion) from a coming tick on: the undo or
    /// redo of a placement. One writer thread (the render thread); the loop takes the sets in order, one per tick,
    /// each on a tick with a finite sample on which the tool holds no workpiece, forgets that workpiece's contact,
    /// lets its next sample carve nothing (no sweep across the jump) and keeps the set for the recording
    /// (pose_changes()). Sets still waiting when a session starts are dropped. Returns false, changing nothing, for
    /// an index out of range, a pose that is not finite or not unit, or when kMaxPoseChanges sets were made over the
    /// loop's life or 16 wait.
    bool set_workpiece_pose(int index, const Pose& pose);
    /// Pose sets the loop has taken so far (any thread).
    std::uint64_t pose_changes_taken() const { return pose_taken_.load(std::memory_order_acquire); }
    /// Every pose set taken this session, in order, with its tick's device time (read after stop()).
    const std::vector<PoseChange>& pose_changes() const { return pose_changes_; }
    /// Most pose sets one session keeps.
    static constexpr std::size_t kMaxPoseChanges = 4096;
    /// Workpieces the loop feels.
    std::size_t workpieces() const { return pieces_.size(); }

private:
    // What the contact stage returns (world frame). The seam where a multi-point renderer replaces
    // the single god-object.
    struct ContactOut {
        Vec3 force_n{0.0};    // N
        Vec3 torque_nm{0.0};  // N*m, about the tool centre
        Vec3 proxy_m{0.0};    // god-object of point 0 (or the tool centre when free), m
        Vec3 object_force_n{0.0};  // of it, the scene objects' part (elastic and reference), N
        bool contact = false;
        bool hip_inside = false;  // point 0 inside material by the snapshot
        int in_contact = 0;   // points in contact
        const MultiPointResult* points = nullptr;  // per-point detail of this tick (of one workpiece's contact)
        const Pose* points_pose = nullptr;         // that workpiece's pose (points are in its model frame)
    };

    void run() noexcept;
    void run_free();  // HapticLoopConfig::free_run: ticks back to back on the tick-count clock
    void begin_session();
    // The contact stage: force and torque on the tool at tool_world against every workpiece's snapshot (less its
    // recent cuts) and the scene objects; dt_s is the damping time step (s).
    ContactOut contact(const Pose& tool_world, double dt_s);
    // Forgets the contact history (workspace jump, declutch).
    void reset_contact();
    // ToolOp::kPlace: while `engaged`, the target workpiece follows tool_world rigidly from where the tool gripped it
    // (the contact forgotten at the grip); returns whether it is held this tick.
    bool place(bool engaged, const Pose& tool_world);
    // The workpiece this tick's sample carves: held while `keep` (carving or placing), else chosen, touched, nearest.
    std::size_t pick_target(const Pose& tool_world, bool keep) const;
    // One tick at loop time now_s: read, pipeline, write, sample, record. False when the device is lost
    // (zero force written). rec gets everything but compute_us.
    bool tick(double now_s, TickRecord& rec);
    // Counters, histograms, record storage and the view for a finished tick.
    void finish(TickRecord& rec, double compute_s);
    // Takes a new tool from set_tool() and the schedule's changes due at device time t_s (loop thread).
    void apply_tool_changes(double device_t_s);
    // Takes the pose sets due on this tick (set_workpiece_pose, cfg_.pose_schedule) unless the tool holds a
    // workpiece (loop thread); device_t_s: the tick's device time.
    void apply_pose_changes(double device_t_s);
    void take_pose(const PoseChange& c);
    // Switches to `tool` (already checked) with contact points scaled from the configured ones.
    void use_tool(const ToolShape& tool);
    // Builds this tick's ToolSample (op kNone when `hold`) and pushes it; `gap` keeps the next sample from carving.
    void push_sample(const devices::DeviceState& state, const Pose& tool_world, const ContactOut& c, bool hold,
                     bool gap, TickRecord& rec);
    // Whether `tool` may replace the configured tool: the same kind, not a mesh, a finite radius > 0, a finite length
    // (> 0 for a flat end), and a configured radius > 0 to scale the contact points from.
    bool tool_change_allowed(const ToolShape& tool) const;

    struct ToolUpdate {
        std::uint64_t serial = 0;  // 0 = none yet
        ToolShape tool{};
    };

    // One workpiece's channels and contact state (loop thread).
    struct Piece {
        TripleBuffer<ActiveSurface>* surface = nullptr;
        SpscRing<ToolSample>* samples = nullptr;
        SpscRing<SequencedSample>* tap = nullptr;
        Aabb bounds_m{};
        Pose world_from_model{};  // its pose now (the configured one until the tool places it)
        Pose model_from_world{};  // its inverse: where the tool meets it
        std::unique_ptr<MultiPointRenderer> contact;
        RecentCuts cuts{};                          // carving sweeps its snapshot may not hold yet
        std::unique_ptr<ActiveSurface> cut_surface;  // the snapshot with them subtracted (RecentCuts::apply)
        const MultiPointResult* result = nullptr;    // its contact on this tick (owned by contact)
        bool touched = false;     // in contact on the previous tick
        bool carve_gap = false;   // its next sample must not carve (its previous one was not pushed)
        std::uint64_t pushed = 0; // samples its ring took since construction
    };

    devices::HapticDevice& device_;
    bool stiffness_capped_ = false;  // declared before cfg_: set while cfg_ is built
    HapticLoopConfig cfg_;
    SafetyLimits limits_;
    std::vector<std::unique_ptr<Piece>> pieces_;  // at least one; the first is "the workpiece" of a single-piece loop
    OutputLimits output_;  // what the device can render (3/5/6 DOF, per-axis limits)
    EwmaFilter filter_;
    EwmaFilter torque_filter_;
    WorkspaceMapper mapper_;
    Watchdog watchdog_;
    SafetyStage safety_;
    Quat world_to_device_;
    std::vector<Pose> start_poses_;  // each workpiece's configured pose (every session starts from them)
    std::size_t target_ = 0;         // the workpiece this tick's sample carves
    bool target_held_ = false;       // the previous tick carved the touched target or placed it: it stays the target
    std::atomic<int> chosen_{-1};    // choose_workpiece (-1: automatic)
    Pose grip_;              // while placing: the workpiece's pose in the tool's frame at the grip
    bool placing_ = false;   // the tool held the workpiece on the previous tick
    Pose grip_before_;       // while placing: the held workpiece's pose at the grip
    Placement placement_;    // the newest placement that ended
    SpscRing<PoseChange> pose_sets_{16};       // set_workpiece_pose (render thread) -> the loop
    std::size_t pose_sets_sent_ = 0;           // writer side
    std::vector<PoseChange> pose_changes_;     // taken (loop thread; reserved kMaxPoseChanges at construction)
    std::atomic<std::uint64_t> pose_taken_{0};
    std::size_t next_pose_change_ = 0;         // cfg_.pose_schedule entries taken
    Pose last_tool_;
    // No carving on the next sample: the first after an invalid sample, a watchdog hold or the speed
    // limit, so a gap never becomes one long swept capsule.
    bool carve_gap_ = false;
    // Per-session tick state (loop thread only).
    double prev_now_s_ = 0.0;
    bool have_prev_now_ = false;
    double prev_device_t_ = 0.0;  // device time of the previous valid sample (NaN: none yet)
    bool manual_session_ = false; // step() mode session open
    std::vector<TickRecord> records_;
    std::size_t recorded_ = 0;
    TripleBuffer<LoopView> view_;
    AtomicHistogram period_hist_;
    AtomicHistogram compute_hist_;
    std::thread thread_;
    std::atomic<bool> stop_requested_{false};
    std::atomic<bool> running_{false};
    std::atomic<std::size_t> ticks_{0}, overruns_{0}, dropped_{0}, stream_dropped_{0}, tap_dropped_{0}, invalid_{0}, trips_{0}, speed_cuts_{0};
    std::atomic<std::size_t> stale_remote_{0};
    std::atomic<bool> device_lost_{false}, realtime_{false}, locked_{false};
    double device_down_s_ = 0.0;  // written by stop() before device_lost_ is set there
    std::atomic<int> realtime_errno_{0}, lock_errno_{0}, reserved_cpu_{-1};
    std::atomic<std::size_t> over_2ms_{0}, over_5ms_{0};
    std::atomic<double> energy_{0.0};
    std::atomic<std::uint16_t> op_{0};  // ToolOp in the low byte, material in the high byte
    std::atomic<std::uint32_t> symmetry_{0};  // symmetry_bits of the samples' Symmetry
    ToolPoints base_points_{};           // the configured contact points (tool at cfg_.tool's size)
    ToolShape tool_{};                   // the tool in use (loop thread)
    TripleBuffer<ToolUpdate> tool_updates_;
    std::uint64_t tool_serial_sent_ = 0; // writer side
    std::uint64_t tool_serial_used_ = 0; // loop side
    std::size_t next_change_ = 0;        // cfg_.tool_schedule entries applied
    double stiffness_cap_n_per_m_ = 0.0; // world stiffness cap of the device under the workspace gain, N/m
    TripleBuffer<MenuDetent> menu_updates_;  // set_menu (render thread) -> the loop
    GrabSpring grab_;                        // the grab's spring (loop thread)
};

}  // namespace tridex::haptics
