// devices/falcon/falcon_device.cpp - lifecycle (firmware, homing gate, LEDs, ramp) and the per-tick exchange.
#include "devices/falcon/falcon_device.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include "core/error.hpp"
#include "core/format.hpp"
#include "devices/device_profiles.hpp"
#include "devices/falcon/falcon_firmware.hpp"

namespace tridex::devices::falcon {

FalconDevice::FalconDevice(std::unique_ptr<FalconTransport> transport, FalconDeviceOptions options)
    : profile_(novint_falcon()), transport_(std::move(transport)), opt_(std::move(options)) {
    if (!transport_) throw Error("FalconDevice: no transport");
    if (!(opt_.period_s > 0.0 && opt_.period_s <= 1.0)) throw Error("FalconDevice: period_s must be in (0, 1] s");
    if (!(opt_.ramp_s >= 0.0)) throw Error("FalconDevice: ramp_s must be >= 0");
}

FalconDevice::~FalconDevice() { close(); }

DeviceLinkStats FalconDevice::link_stats() const {
    DeviceLinkStats l;
    l.exchanges = stats_.exchanges;
    l.missed_frames = stats_.missed_frames;
    l.malformed_frames = stats_.malformed_frames;
    l.zeroed_ticks = stats_.zeroed_ticks;
    l.exchange_mean_s = stats_.exchange_mean_s;
    l.exchange_max_s = stats_.exchange_max_s;
    l.homed_at_s = stats_.homed_at_s;
    l.firmware_attempts = stats_.firmware_attempts;
    return l;
}

void FalconDevice::on_open() {
    transport_->open();
    framer_.reset();
    ticks_ = 0;
    vanished_ = false;
    have_pos_ = false;
    stats_ = FalconLinkStats{};
    leds_ = kLedRed;
    homing_mode_ = false;
    cmd_ = FalconCommand{{0, 0, 0}, leds_, homing_mode_};
    // The bridge in normal mode first (libnifalcon's open), so that firmware already running can answer the probe.
    if (std::string error; !set_normal_mode(*transport_, 1000, error)) {
        transport_->close();
        throw Error("Novint Falcon (" + transport_->describe() + "): its USB bridge did not take normal mode: " + error +
                    "; unplug the Falcon's USB, plug it back in and try again");
    }
    if (firmware_running(*transport_)) return;
    std::vector<std::uint8_t> image = opt_.firmware_image;
    if (image.empty()) {
        if (opt_.firmware_path.empty()) {
            transport_->close();
            throw Error(firmware_missing_message());
        }
        try {
            image = read_firmware_file(opt_.firmware_path);
        } catch (...) {
            transport_->close();
            throw;
        }
    }
    FirmwareLoadOptions lo;
    lo.attempts = opt_.firmware_attempts;
    const FirmwareLoadReport r = load_firmware(*transport_, image, lo);
    stats_.firmware_attempts = r.attempts;
    if (!r.ok || !firmware_running(*transport_)) {
        transport_->close();
        throw Error("Novint Falcon (" + transport_->describe() + "): the firmware did not load after " +
                    std::to_string(r.attempts) +
                    " attempts: " + (r.error.empty() ? "no state frames after the load" : r.error) +
                    "; unplug the Falcon's power and USB, plug them back in and try again");
    }
}

void FalconDevice::on_home() {
    // libnifalcon's documented order (FalconFirmware.h, "Homing Mode"): homing mode on in every command from here
    // on, the user pulls the grip all the way out and pushes it in, the host waits for the three homing bits; the
    // bit stays set in every later command, or the Falcon does not stay homed.
    leds_ = kLedRed;
    homing_mode_ = true;
    const int limit = static_cast<int>(std::ceil(opt_.homing_timeout_s / opt_.period_s));
    std::optional<FalconState> s;
    for (int i = 0; i < limit; ++i) {
        cmd_ = FalconCommand{{0, 0, 0}, leds_, homing_mode_};
        const TransferStatus st = exchange(s);
        ++stats_.homing_exchanges;
        if (st == TransferStatus::kNoDevice)
            throw Error("Novint Falcon (" + transport_->describe() + "): unplugged while homing");
        if (s && (s->homing_status & kAllHomed) == kAllHomed) {
            leds_ = kLedBlue;
            cmd_ = FalconCommand{{0, 0, 0}, leds_, homing_mode_};
            stats_.homed_at_s = static_cast<double>(ticks_) * opt_.period_s;
            return;
        }
    }
    cmd_ = FalconCommand{{0, 0, 0}, leds_, homing_mode_};
    throw Error("Novint Falcon: not homed after " + format_number(opt_.homing_timeout_s) +
                " s: pull the grip all the way out toward you, then push it all the way in, and try again");
}

void FalconDevice::on_enable() {
    leds_ = kLedGreen;
    ramp_ticks_ = 0;
    cmd_ = FalconCommand{{0, 0, 0}, leds_, homing_mode_};
}

void FalconDevice::on_disable() noexcept {
    leds_ = kLedBlue;
    send_zero();
}

void FalconDevice::on_close() noexcept {
    leds_ = 0;
    send_zero();
    transport_->close();
}

void FalconDevice::send_zero() noexcept {
    cmd_ = FalconCommand{{0, 0, 0}, leds_, homing_mode_};
    if (vanished_ || transport_->unplugged()) return;
    std::optional<FalconState> s;
    try {
        (void)exchange(s);
    } catch (...) {
        raise_fault(kFaultIo);
    }
}

namespace {

// std::chrono::steady_clock now, s.
double steady_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

TransferStatus FalconDevice::exchange(std::optional<FalconState>& state) {
    const Frame out = encode_command(cmd_);
    std::array<std::uint8_t, kUsbPacketBytes> packet{};
    std::size_t got = 0;
    ++ticks_;
    const TransferStatus st = transport_->exchange(out, packet, opt_.exchange_timeout_us, got);
    state.reset();
    if (st != TransferStatus::kOk) return st;
    std::span<const std::uint8_t> data;
    const std::optional<ModemStatus> modem = split_in_packet(std::span<const std::uint8_t>(packet.data(), got), data);
    if (!modem) return TransferStatus::kOk;
    if (modem->line_error()) ++stats_.line_errors;
    const std::uint64_t bad_before = framer_.malformed();
    state = framer_.feed(data);
    stats_.malformed_frames += framer_.malformed() - bad_before;
    if (modem->line_error()) state.reset();
    return TransferStatus::kOk;
}

bool FalconDevice::do_read(DeviceState& out) {
    if (vanished_) return false;
    if (state() == DeviceLifecycle::kClosed) return false;
    std::optional<FalconState> s;
    const std::uint64_t bad_before = stats_.malformed_frames;
    const TransferStatus st = exchange(s);
    ++stats_.exchanges;
    const double dt = transport_->last_exchange_s();
    stats_.exchange_max_s = std::max(stats_.exchange_max_s, dt);
    stats_.exchange_mean_s += (dt - stats_.exchange_mean_s) / static_cast<double>(stats_.exchanges);
    if (st == TransferStatus::kNoDevice || transport_->unplugged()) {
        vanished_ = true;
        fault_tick_ = true;
        cmd_ = FalconCommand{{0, 0, 0}, leds_, homing_mode_};
        raise_fault(kFaultIo);
        return false;
    }
    // A frame that arrived but was malformed in the same packet as a good one still counts as a fault.
    const bool malformed = stats_.malformed_frames != bad_before;
    if (!s || malformed || st != TransferStatus::kOk) {
        ++stats_.missed_frames;
        ++missed_run_;
        fault_tick_ = true;
        raise_fault(kFaultIo);
        if (static_cast<double>(missed_run_) * opt_.period_s >= opt_.stall_vanish_s) {
            vanished_ = true;
            return false;
        }
    }
    if (s) {
        missed_run_ = 0;
        const Vec3 theta(kin_.encoder_to_theta(s->encoder[0]), kin_.encoder_to_theta(s->encoder[1]),
                         kin_.encoder_to_theta(s->encoder[2]));
        const FalconKinematics::Forward fk =
            kin_.forward(theta, have_pos_ ? pos_ : FalconKinematics::home_m(), 1e-10, 20);
        if (fk.converged) {
            // The interval that really passed since the last measured position: missed frames in between count
            // (device time), and so does a loop that ran late (the monotonic clock); the larger of the two.
            const double now_s = opt_.clock_s ? opt_.clock_s() : steady_seconds();
            const double elapsed_s = std::max(static_cast<double>(ticks_ - pos_tick_) * opt_.period_s, now_s - pos_clock_s_);
            vel_ = have_pos_ && elapsed_s > 0.0 ? (fk.position - pos_) / elapsed_s : Vec3(0.0);
            pos_ = fk.position;
            pos_tick_ = ticks_;
            pos_clock_s_ = now_s;
            have_pos_ = true;
        } else {
            fault_tick_ = true;  // encoders no pose fits: treat as a malformed frame
            raise_fault(kFaultIo);
        }
        grip_ = s->grip_buttons;
    }
    out.t_s = static_cast<double>(ticks_) * opt_.period_s;
    out.pose.position = have_pos_ ? pos_ : FalconKinematics::home_m();
    out.pose.orientation = Quat(1.0, 0.0, 0.0, 0.0);
    out.velocity_m_s = vel_;
    out.buttons = grip_;
    return true;
}

void FalconDevice::do_write(const Vec3& force_n, const Vec3&) {
    cmd_ = FalconCommand{{0, 0, 0}, leds_, homing_mode_};
    if (fault_tick_) {
        // A missed or malformed frame this tick: zero force now, and ramp in again once frames come back.
        fault_tick_ = false;
        ramp_ticks_ = 0;
        ++stats_.zeroed_ticks;
        return;
    }
    if (state() != DeviceLifecycle::kEnabled || !have_pos_ || vanished_) return;
    ++ramp_ticks_;
    const double ramp =
        opt_.ramp_s > 0.0 ? std::min(1.0, static_cast<double>(ramp_ticks_) * opt_.period_s / opt_.ramp_s) : 1.0;
    const Vec3 f = force_n * ramp;
    if (f == Vec3(0.0)) return;
    const std::optional<Vec3> tau = kin_.force_to_torque(pos_, f);
    if (!tau) return;  // out of reach or singular: no force rather than a wild one
    bool clamped = false;
    cmd_.motor = torque_to_command(*tau, kMaxMotorCommand, &clamped);
    if (clamped) ++stats_.clamped_commands;
}

}  // namespace tridex::devices::falcon
