// haptics/watchdog.cpp - the three trip conditions and the re-arm delay.
#include "haptics/watchdog.hpp"

#include <cmath>

namespace tridex::haptics {

Watchdog::Watchdog(double period_s, double stale_timeout_s, double stall_factor, double rearm_s)
    : period_s_(period_s), stale_timeout_s_(stale_timeout_s), stall_factor_(stall_factor), rearm_s_(rearm_s) {}

void Watchdog::reset() {
    primed_ = false;
    tripped_ = false;
    last_device_t_ = 0.0;
    advanced_at_ = 0.0;
    bad_device_t_ = 0.0;
}

WatchdogStatus Watchdog::update(double loop_time_s, double device_time_s, bool finite) {
    WatchdogStatus st;
    const bool t_ok = std::isfinite(device_time_s);
    if (!finite || !t_ok || !std::isfinite(loop_time_s)) st.causes |= kWatchdogNonFinite;
    if (!primed_) {
        if (t_ok && std::isfinite(loop_time_s)) {
            primed_ = true;
            last_device_t_ = device_time_s;
            advanced_at_ = loop_time_s;
        }
    } else if (t_ok) {
        if (device_time_s > last_device_t_) {
            if (device_time_s - last_device_t_ > stall_factor_ * period_s_) st.causes |= kWatchdogStalled;
            last_device_t_ = device_time_s;
            advanced_at_ = loop_time_s;
        } else if (loop_time_s - advanced_at_ > stale_timeout_s_) {
            st.causes |= kWatchdogStale;
        }
    } else if (std::isfinite(loop_time_s) && loop_time_s - advanced_at_ > stale_timeout_s_) {
        st.causes |= kWatchdogStale;  // no usable time stamp for too long either
    }

    if (st.causes != 0) {
        if (!tripped_) {
            tripped_ = true;
            st.tripped_now = true;
            ++trips_;
        }
        if (t_ok) bad_device_t_ = device_time_s;
        else bad_device_t_ = last_device_t_;
        st.force_allowed = false;
        return st;
    }
    if (tripped_) {
        if (device_time_s - bad_device_t_ >= rearm_s_) {
            tripped_ = false;
            st.rearmed_now = true;
        } else {
            st.force_allowed = false;
        }
    }
    return st;
}

}  // namespace tridex::haptics
