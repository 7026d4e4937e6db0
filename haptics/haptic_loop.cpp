// haptics/haptic_loop.cpp - the haptic thread: absolute-deadline ticks and the per-tick pipeline.
#include "haptics/haptic_loop.hpp"

#include <algorithm>
#include <sys/prctl.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <string>

#include "core/error.hpp"
#include "haptics/force_clamp.hpp"

namespace tridex::haptics {

namespace {

std::int64_t now_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000LL + ts.tv_nsec;
}

void sleep_until_ns(std::int64_t t_ns) {
    timespec ts{};
    ts.tv_sec = static_cast<time_t>(t_ns / 1'000'000'000LL);
    ts.tv_nsec = static_cast<long>(t_ns % 1'000'000'000LL);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
}

bool finite_state(const devices::DeviceState& s) {
    const Quat& q = s.pose.orientation;
    return std::isfinite(s.t_s) && is_finite(s.pose.position) && is_finite(s.velocity_m_s) && std::isfinite(q.w) &&
           std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
}

[[noreturn]] void bad(const std::string& field, double value, const char* rule) {
    throw Error("HapticLoopConfig." + field + " = " + std::to_string(value) + " " + rule);
}

HapticLoopConfig validated(HapticLoopConfig c) {
    if (!(std::isfinite(c.period_s) && c.period_s >= 1e-5 && c.period_s <= 0.1))
        bad("period_s", c.period_s, "must be in [1e-5, 0.1] s");
    if (!(std::isfinite(c.ewma_alpha) && c.ewma_alpha >= 0.0 && c.ewma_alpha < 1.0))
        bad("ewma_alpha", c.ewma_alpha, "must be in [0, 1)");
    if (!(std::isfinite(c.workspace_scale) && c.workspace_scale > 0.0))
        bad("workspace_scale", c.workspace_scale, "must be finite and > 0");
    if (!is_finite(c.device_to_world.position)) bad("device_to_world.position.x", c.device_to_world.position.x,
                                                     "(or y, z) is not finite");
    const Quat& q = c.device_to_world.orientation;
    const double qn = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    if (!(std::abs(qn - 1.0) <= 1e-6)) bad("device_to_world.orientation |q|", qn, "must be 1 (unit quaternion)");
    c.device_to_world.orientation = q / qn;
    return c;
}

}  // namespace

HapticLoop::HapticLoop(devices::HapticDevice& device, TripleBuffer<ActiveSurface>& surface,
                       SpscRing<ToolSample>& samples, HapticLoopConfig cfg)
    : device_(device),
      surface_(surface),
      samples_(samples),
      cfg_(validated(cfg)),
      max_force_n_(device.profile().max_force_n),
      god_(cfg_.contact),
      filter_(cfg_.ewma_alpha),
      world_to_device_(glm::conjugate(cfg_.device_to_world.orientation)) {
    if (!(std::isfinite(max_force_n_) && max_force_n_ >= 0.0))
        throw Error("HapticLoop: device profile '" + device.profile().name +
                    "' max_force_n = " + std::to_string(max_force_n_) + " must be finite and >= 0");
    records_.assign(cfg_.max_ticks, TickRecord{});  // allocated and touched here, never in the loop
}

HapticLoop::~HapticLoop() { stop(); }

void HapticLoop::start() {
    if (running()) return;
    if (thread_.joinable()) thread_.join();  // ended by itself (device lost)
    records_.resize(cfg_.max_ticks);         // back to full size after a previous stop() trimmed it
    recorded_ = 0;
    ticks_ = 0;
    overruns_ = 0;
    dropped_ = 0;
    invalid_ = 0;
    device_lost_ = false;
    god_.reset();
    filter_.reset();
    last_hip_ = cfg_.device_to_world.position;
    stop_requested_.store(false, std::memory_order_relaxed);
    running_.store(true, std::memory_order_release);
    thread_ = std::thread(&HapticLoop::run, this);
}

void HapticLoop::stop() {
    stop_requested_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
    records_.resize(recorded_);  // shrinking never reallocates; start() grows it back in place
}

LoopStats HapticLoop::stats() const {
    LoopStats s;
    s.ticks = ticks_.load(std::memory_order_relaxed);
    s.overruns = overruns_.load(std::memory_order_relaxed);
    s.samples_dropped = dropped_.load(std::memory_order_relaxed);
    s.invalid_samples = invalid_.load(std::memory_order_relaxed);
    s.device_lost = device_lost_.load(std::memory_order_relaxed);
    return s;
}

TickRecord HapticLoop::tick(const devices::DeviceState& state, double dt_s) {
    const Vec3 hip = cfg_.device_to_world.apply(cfg_.workspace_scale * state.pose.position);
    last_hip_ = hip;
    const ContactResult c = god_.update(surface_.latest(), hip, dt_s);
    // Clamp before the filter too: a non-finite or huge contact force must not poison the filter state.
    Vec3 force_world = clamp_force(filter_.apply(clamp_force(c.force_n, max_force_n_)), max_force_n_);
    if (!is_finite(filter_.value())) {
        filter_.reset();
        force_world = Vec3(0.0);
    }
    device_.write(world_to_device_ * force_world, Vec3(0.0));

    ToolSample sample;
    sample.t_s = state.t_s;
    sample.position = hip;
    sample.orientation = glm::normalize(cfg_.device_to_world.orientation * state.pose.orientation);
    sample.radius_m = cfg_.contact.tool_radius_m;
    sample.op = cfg_.op;
    sample.buttons = state.buttons;
    if (!samples_.try_push(sample)) dropped_.fetch_add(1, std::memory_order_relaxed);

    TickRecord rec;
    rec.hip_m = hip;
    rec.proxy_m = c.proxy_m;
    rec.force_n = force_world;
    rec.contact = c.contact;
    return rec;
}

void HapticLoop::run() noexcept {
    prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);  // wake within ~1 ns of the deadline, not the 50 us default
    const std::int64_t period_ns = std::llround(cfg_.period_s * 1e9);
    const std::int64_t t0 = now_ns();
    std::int64_t next = t0;
    std::int64_t prev_start = -1;
    double prev_device_t = std::nan("");  // device time of the previous valid sample
    devices::DeviceState state;
    try {
        while (!stop_requested_.load(std::memory_order_acquire)) {
            sleep_until_ns(next);
            const std::int64_t start = now_ns();
            if (!device_.read(state)) {
                device_lost_.store(true, std::memory_order_relaxed);
                break;
            }
            TickRecord rec;
            // A finite device position can still map to a non-finite world HIP (huge workspace_scale).
            const bool valid = finite_state(state) &&
                               is_finite(cfg_.device_to_world.apply(cfg_.workspace_scale * state.pose.position));
            if (valid) {
                // Time step of the contact damping: the device's own clock, else the nominal period.
                // Bounded to [period/10, 10*period] so a glitching clock cannot blow up the damping term.
                const double dt = state.t_s > prev_device_t
                                      ? std::clamp(state.t_s - prev_device_t, 0.1 * cfg_.period_s, 10.0 * cfg_.period_s)
                                      : cfg_.period_s;
                prev_device_t = state.t_s;
                rec = tick(state, dt);
            } else {
                device_.write(Vec3(0.0), Vec3(0.0));
                invalid_.fetch_add(1, std::memory_order_relaxed);
                rec.hip_m = last_hip_;
                rec.proxy_m = last_hip_;
                rec.valid_sample = false;
            }
            const std::int64_t end = now_ns();
            rec.t_s = static_cast<double>(start - t0) * 1e-9;
            rec.period_us = prev_start < 0 ? 0.0f : static_cast<float>(static_cast<double>(start - prev_start) * 1e-3);
            rec.compute_us = static_cast<float>(static_cast<double>(end - start) * 1e-3);
            prev_start = start;
            if (recorded_ < records_.size()) records_[recorded_++] = rec;
            ticks_.fetch_add(1, std::memory_order_relaxed);
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
    try {
        device_.write(Vec3(0.0), Vec3(0.0));
    } catch (...) {
    }
    running_.store(false, std::memory_order_release);
}

}  // namespace tridex::haptics
