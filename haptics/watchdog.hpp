// haptics/watchdog.hpp - cuts the force on non-finite, stale or stalled device data.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tridex::haptics {

/// Why the watchdog holds the force at zero on a tick (bit flags; 0 = healthy sample).
enum WatchdogCause : std::uint8_t {
    kWatchdogNonFinite = 1,  ///< the sample has a NaN or infinite time, pose or velocity
    kWatchdogStale = 2,      ///< the device time stamp has not advanced for longer than stale_timeout_s
    kWatchdogStalled = 4,    ///< the device clock stepped more than stall_factor * period since the last tick
};

/// The watchdog's verdict for one tick.
struct WatchdogStatus {
    std::uint8_t causes = 0;     ///< WatchdogCause bits found on this tick
    bool force_allowed = true;   ///< false: command zero force and torque this tick
    bool tripped_now = false;    ///< this tick started a trip (counted in trips())
    bool rearmed_now = false;    ///< this tick ended a trip: force is allowed again (restart the ramp)
};

/// Watchdog of the haptic loop. Each tick it gets the loop clock (s), the sample's device time (s)
/// and whether the sample is finite, and decides whether force may be sent:
/// - non-finite sample: trips at once (the force of that very tick is zero);
/// - stale: the device time has not increased for more than stale_timeout_s of loop time (a frozen
///   driver, a replay stuck on one frame): trips at the first tick past the timeout;
/// - stalled: the device clock advanced by more than stall_factor * period_s since the previous tick
///   (the loop or the device missed that many deadlines): trips on that tick. The tick period is
///   measured on the device clock, the clock the forces act in: a simulated device, which steps once
///   per read, never stalls however late the thread wakes, while hardware time-stamped in real time
///   does. The device must therefore advance about one period per tick (a device whose clock steps
///   more than stall_factor periods per read, e.g. a 1 ms simulated step under a 0.1 ms loop period,
///   trips on every tick). Nothing in software can act during the stall itself; the zero goes out
///   with the first tick after it (a device-side watchdog, like the Omni driver's own, covers the gap).
/// While tripped the force stays zero; once no cause has been seen for rearm_s of device time the
/// watchdog re-arms (rearmed_now) and the loop ramps the force in again. A trip is counted once per
/// episode (healthy -> tripped). The first update after construction or reset() only records the
/// clocks (no stale or stall test). Allocation-free, O(1).
class Watchdog {
public:
    /// period_s: nominal tick period, s; stale_timeout_s, stall_factor, rearm_s as in SafetyConfig
    /// (the caller validates them).
    Watchdog(double period_s, double stale_timeout_s, double stall_factor, double rearm_s);

    /// One tick: loop_time_s (s, the loop clock), device_time_s (s, the sample's stamp, may be NaN
    /// when the sample is non-finite), finite = the whole sample is finite.
    WatchdogStatus update(double loop_time_s, double device_time_s, bool finite);
    /// Healthy, no history, trip count kept.
    void reset();
    /// Trips since construction (reset() does not clear it; clear_trips() does).
    std::size_t trips() const { return trips_; }
    /// Sets the trip count to 0.
    void clear_trips() { trips_ = 0; }
    /// True while the force is held at zero.
    bool tripped() const { return tripped_; }

private:
    double period_s_, stale_timeout_s_, stall_factor_, rearm_s_;
    bool primed_ = false;
    bool tripped_ = false;
    double last_device_t_ = 0.0;  // newest finite device time seen
    double advanced_at_ = 0.0;    // loop time at which the device time last increased
    double bad_device_t_ = 0.0;   // device time of the last tick with a cause (newest finite one)
    std::size_t trips_ = 0;
};

}  // namespace tridex::haptics
