// devices/haptic_device.hpp - the abstract haptic device: what it can do, one sample, read and write.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

#include "core/aabb.hpp"
#include "core/active_surface.hpp"
#include "core/math.hpp"
#include "core/pose.hpp"

namespace tridex::devices {

/// What a haptic device can do, in SI units and in the device frame.
struct DeviceProfile {
    std::string name;                    ///< human-readable model name
    Aabb workspace_m;                    ///< reachable box of the stylus tip in the device frame, m
    double max_force_n = 0.0;            ///< continuous force limit, N (the loop clamps |F| to it)
    double max_torque_nm = 0.0;          ///< continuous torque limit, N*m; 0 for 3-DOF output
    double max_stiffness_n_per_m = 0.0;  ///< highest virtual-wall stiffness that stays stable at 1 kHz, N/m
    int dof_in = 0;                      ///< sensed degrees of freedom (6 = position + orientation)
    int dof_out = 0;                     ///< actuated degrees of freedom (3 = force only)
    /// Per-axis continuous force limits in the device frame, N (|F_x|, |F_y|, |F_z|); unset = max_force_n on
    /// every axis. devices::axis_limits() reads it.
    std::optional<Vec3> max_force_axis_n;
    /// Per-axis continuous torque limits in the device frame, N*m; 0 on an axis = not actuated; unset =
    /// derived from max_torque_nm and dof_out (devices::axis_limits()).
    std::optional<Vec3> max_torque_axis_nm;
    /// Per-axis range of the stylus orientation about its home orientation, rad: |angle| <= limit about
    /// device x, y, z (e.g. the wand's pitch and yaw); unset = not known, no limit is modelled.
    std::optional<Vec3> rotation_range_rad;

    /// SensAble (3D Systems) PHANTOM Omni, from its published specification sheet:
    /// workspace 160 x 120 x 70 mm (6.4 x 4.8 x 2.8 in, width x height x depth = device x, y, z),
    /// here centred on the device origin; max_force_n = 0.88 N, the sheet's "continuous exertable
    /// force (24 h)" (the 3.3 N "maximum exertable force at nominal position" is a peak the motors
    /// cannot hold, so it is not used as the safety limit); max_stiffness_n_per_m = 700 N/m
    /// (0.7 N/mm, DESIGN.md; the sheet lists 1.02 N/mm on its weakest axis, z, so 0.7 keeps a margin);
    /// 6-DOF sensing, 3-DOF force output, no torque.
    static DeviceProfile phantom_omni();
};

/// One sample from the device, in the device frame.
struct DeviceState {
    double t_s = 0.0;            ///< device time, s
    Pose pose;                   ///< stylus pose: tip position (m) and orientation (unit quaternion)
    Vec3 velocity_m_s{0.0};      ///< tip velocity, m/s
    std::uint32_t buttons = 0;   ///< button bits, bit i = button i pressed
    double joystick_y = 0.0;     ///< a joystick's y in [-1, 1] (a Flystick's, DriverCapabilities::joystick); else 0
};

/// A tool sample computed by a contact loop next to the device (the net driver in local haptic rendering: the
/// device server's god-object loop), world frame, SI. The session sculpts with it instead of its own contact.
struct RemoteToolSample {
    Pose tool_world;       ///< the HIP: the stylus through the server's workspace mapping, world m
    Vec3 proxy_m{0.0};     ///< the god-object (proxy) position, on the surface when in contact, world m
    Vec3 force_n{0.0};     ///< force the server's loop rendered on this tick (after its safety stages), world N
    bool contact = false;  ///< the god-object touched the surface
    bool hold = false;     ///< the server's loop held carving on this tick (its watchdog, over speed, invalid sample)
    /// Not this tick's sample: no new device state came with it since the previous read (the link stalled or is
    /// down), so its pose and force are an earlier tick's; the loop logs its force as stale, not as the force the
    /// device got this tick, and carves nothing with it.
    bool stale = false;
};

/// Where a device is in its life: closed -> open -> homed -> enabled (forces flow) -> homed -> closed.
enum class DeviceLifecycle : std::uint8_t {
    kClosed = 0,   ///< not connected (the initial state, and after close())
    kOpen = 1,     ///< connected, sampling allowed; position not yet calibrated
    kHomed = 2,    ///< calibrated (homed): read() gives poses in the device frame; forces still off
    kEnabled = 3,  ///< forces are sent: write() reaches the device's motors
};

/// "closed", "open", "homed" or "enabled".
const char* to_string(DeviceLifecycle state);

/// Fault bits of a device's status channel (DeviceStatus::faults); several can be set at once.
enum DeviceFault : std::uint32_t {
    kFaultNone = 0,
    kFaultNotHomed = 1u << 0,         ///< enable() was asked of a device that was never homed
    kFaultOverTemperature = 1u << 1,  ///< the driver reported its motors too hot (forces cut by the device)
    kFaultForceLimit = 1u << 2,       ///< a written force or torque exceeded the profile's limits and was cut
    kFaultVanished = 1u << 3,         ///< read() failed: unplugged, powered off, end of a replay
    kFaultNonFinite = 1u << 4,        ///< a non-finite force or torque was written (sent as zero)
    kFaultIo = 1u << 5,               ///< a transport error (USB, network) that the driver survived
};

/// The fault bits of `faults` as words ("not_homed, force_limit"); "none" for 0.
std::string fault_names(std::uint32_t faults);

/// A snapshot of a device's status channel: its lifecycle state, the fault bits raised since open() (sticky
/// until clear_faults()), and counts of what the lifecycle guard did to writes.
struct DeviceStatus {
    DeviceLifecycle state = DeviceLifecycle::kClosed;
    std::uint32_t faults = kFaultNone;    ///< DeviceFault bits
    std::uint64_t writes = 0;             ///< write() calls
    std::uint64_t writes_suppressed = 0;  ///< writes sent as zero force because the device was not enabled
    std::uint64_t writes_clamped = 0;     ///< writes cut to the profile's limits (or zeroed for non-finite values)
};

/// What a driver with a transport (USB, network) measured on it; drivers without one report exchanges = 0.
struct DeviceLinkStats {
    std::uint64_t exchanges = 0;         ///< exchanges (one per read) in the loop
    std::uint64_t missed_frames = 0;     ///< exchanges that brought no well-formed sample
    std::uint64_t malformed_frames = 0;  ///< frames refused as malformed
    std::uint64_t zeroed_ticks = 0;      ///< ticks whose force was forced to zero by a link fault
    double exchange_mean_s = 0.0;        ///< exchange time (send to sample), mean and max, s
    double exchange_max_s = 0.0;
    double homed_at_s = -1.0;   ///< device time from open() at which homing finished, s; -1 = none reported
    int firmware_attempts = 0;  ///< firmware-load attempts at open() (0: none needed)
    /// Network drivers (net): "distributed" or "local" (where the contact loop runs); "" for other drivers.
    std::string link_mode{};
    bool sealed = false;                 ///< network drivers: every datagram authenticated and encrypted (a key given)
    std::uint64_t seal_refused = 0;      ///< sealed: datagrams refused as not the peer's (wrong key, replayed, ...)
    double rtt_median_us = 0.0;          ///< round-trip time of the link, median, us
    double rtt_p99_us = 0.0;             ///< round-trip time, 99th percentile, us
    std::uint64_t lost = 0;              ///< datagrams lost (sequence gaps seen by either end)
    double rate_hz = 0.0;                ///< device states received per second
    std::uint64_t stale_snapshots = 0;   ///< local mode: snapshots that reached the server too old to cover the tool
    /// Local mode: reads whose tool sample was an earlier tick's (no new device state came), logged as stale.
    std::uint64_t stale_tool_samples = 0;
    std::uint64_t link_outages = 0;      ///< times the link went silent past the watchdog (force zeroed)
    std::uint64_t server_watchdog_trips = 0;  ///< times the server's watchdog zeroed the force
    std::string link_events{};           ///< what happened to the link, for the user ("" = nothing to say)
    /// Network drivers: how long the link has been down at the time of the call (no device state for the driver's
    /// watchdog time and none since), s; 0 while it is up. A session that ends with its link down lost its device.
    double down_for_s = 0.0;
};

/// Abstract haptic device (CHAI3D/HAPI style: one interface for hardware, simulated and replayed devices).
///
/// Lifecycle (what real hardware needs): open() connects, home() calibrates the position sensors (a Falcon
/// or an Omni needs its arm moved to a home pose once per power-up), enable() lets forces through, disable()
/// sends zero force and stops them, close() disconnects. The base class enforces the order and the force
/// rule: write() passes a force to the driver only while the device is enabled, sending zero force in every
/// other state; every force that does pass is bounded by the profile's limits (a last resort: the haptic
/// loop's safety stage clamps first) and a non-finite one is sent as zero. bring_up() runs whatever of
/// open/home/enable is still due. status() is a lock-free snapshot any thread may read.
///
/// read() returns false when the device has vanished (unplugged, end of a replay): the fault kFaultVanished
/// is raised and the caller commands zero force and stops. write() sends force (N) and torque (N*m), both
/// in the device frame. read() and write() are driven from one thread (the haptic loop) and must not
/// allocate, lock or block for longer than a fraction of the loop period; the lifecycle calls are made from
/// the thread that owns the session, never concurrently with read()/write() of another thread except
/// disable() racing nothing (the loop calls it itself when it stops).
///
/// Writing a driver: derive, return a DeviceProfile from profile(), implement do_read() and do_write(), and
/// override the on_* hooks the hardware needs (they may throw tridex::Error with a message for the user);
/// then register a factory (devices/registry/device_registry.hpp).
class HapticDevice {
public:
    virtual ~HapticDevice();
    /// The device's capabilities; constant for the device's lifetime.
    virtual const DeviceProfile& profile() const = 0;

    /// Connects (closed -> open). Throws tridex::Error when the driver cannot (no such unit, permission);
    /// does nothing when already open.
    void open();
    /// Calibrates (open -> homed); opens first when closed. Throws tridex::Error when the driver cannot home
    /// (e.g. the arm is not at its home pose); does nothing when already homed or enabled.
    void home();
    /// Lets forces through (homed -> enabled). Throws tridex::Error and raises kFaultNotHomed when the device
    /// was never homed; does nothing when already enabled.
    void enable();
    /// Sends zero force and stops forces (enabled -> homed). Never throws; does nothing unless enabled.
    void disable() noexcept;
    /// Disables, then disconnects (-> closed). Never throws (a driver error is raised as kFaultIo).
    void close() noexcept;
    /// open(), home() and enable(), whichever are still due. Throws as they do.
    void bring_up();

    /// Fetches the newest sample into out (in any lifecycle state: a driver that cannot sample before
    /// open() returns false). Returns false (out unspecified) when the device is gone, raising kFaultVanished.
    bool read(DeviceState& out);
    /// Commands force_n (N) and torque_nm (N*m) in the device frame until the next write: zero unless the
    /// device is enabled; cut to the profile's limits (max_force_n; max_torque_nm, or 0 for a device without
    /// torque output) and zero for non-finite values, raising kFaultForceLimit / kFaultNonFinite.
    void write(const Vec3& force_n, const Vec3& torque_nm);

    /// The lifecycle state (any thread).
    DeviceLifecycle state() const { return static_cast<DeviceLifecycle>(state_.load(std::memory_order_acquire)); }
    /// A snapshot of the status channel (any thread, lock-free).
    DeviceStatus status() const;
    /// Raises fault bits (drivers report over-temperature, I/O errors and the like here; any thread).
    void raise_fault(std::uint32_t faults) { faults_.fetch_or(faults, std::memory_order_acq_rel); }
    /// Clears every fault bit (after the user has seen them).
    void clear_faults() { faults_.store(kFaultNone, std::memory_order_release); }
    /// The driver's transport measurements (not thread-safe: read after the loop stopped); none by default.
    virtual DeviceLinkStats link_stats() const { return {}; }
    /// Called by the thread that publishes active-surface snapshots (the sculpt thread; never the haptic thread)
    /// with each new snapshot. Drivers that render contact next to the device (net in local mode) forward the
    /// newest to it; others ignore it. May allocate and lock; must not wait on the haptic thread.
    virtual void observe_surface(const ActiveSurface& surface) { (void)surface; }
    /// Called by the haptic loop (haptic thread) when the tool is resized during a session: the contact points'
    /// positions and radii are now `scale` (> 0) times those the session configured. Drivers that render contact
    /// next to the device (net in local mode) forward it; others ignore it. Must not block, allocate or do I/O.
    virtual void observe_tool_scale(double scale) { (void)scale; }
    /// Called once per displayed frame by the session's frame loop on the thread that owns the window (GLFW's main
    /// thread), while the haptic thread may be in read(). Drivers whose input API must run there (GLFW's joystick
    /// and gamepad functions) poll it here and hand the result to read() through a lock-free snapshot; others
    /// ignore it. Must not block for long (a frame's budget) and must not throw.
    virtual void poll_on_main_thread() noexcept {}
    /// The tool sample that a contact loop next to the device computed for the sample the last read() returned
    /// (haptic thread, after read()); false when the device renders no contact itself (every local driver) or sent
    /// none for it. Must not block or allocate.
    virtual bool remote_tool(RemoteToolSample& out) const {
        (void)out;
        return false;
    }

protected:
    /// Driver hook of open(): connect. Throw tridex::Error naming the device on failure.
    virtual void on_open() {}
    /// Driver hook of home(): calibrate. Throw tridex::Error saying what the user must do on failure.
    virtual void on_home() {}
    /// Driver hook of enable(), after which forces flow (e.g. switch the amplifiers on).
    virtual void on_enable() {}
    /// Driver hook of disable(), after zero force was written (e.g. switch the amplifiers off). Must not throw.
    virtual void on_disable() noexcept {}
    /// Driver hook of close(): disconnect. Must not throw.
    virtual void on_close() noexcept {}
    /// The driver's sample read: as read(), without the lifecycle bookkeeping.
    virtual bool do_read(DeviceState& out) = 0;
    /// The driver's force write: already gated and bounded by write().
    virtual void do_write(const Vec3& force_n, const Vec3& torque_nm) = 0;

private:
    void set_state(DeviceLifecycle s) { state_.store(static_cast<std::uint8_t>(s), std::memory_order_release); }

    std::atomic<std::uint8_t> state_{static_cast<std::uint8_t>(DeviceLifecycle::kClosed)};
    std::atomic<std::uint32_t> faults_{kFaultNone};
    std::atomic<std::uint64_t> writes_{0}, suppressed_{0}, clamped_{0};
};

}  // namespace tridex::devices
