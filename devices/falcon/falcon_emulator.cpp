// devices/falcon/falcon_emulator.cpp - the emulated bridge, loader, firmware and mechanism, and the fault injector.
#include "devices/falcon/falcon_emulator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "devices/device_profiles.hpp"

namespace tridex::devices::falcon {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kTornFirstBytes = 7;

ScriptedPath hold_home() { return ScriptedPath::hold(FalconKinematics::home_m()); }

}  // namespace

FalconEmulator::FalconEmulator(FalconEmulatorConfig config)
    : cfg_(std::move(config)),
      sim_(novint_falcon(), cfg_.hand_path ? *cfg_.hand_path : hold_home(), cfg_.hand, cfg_.period_s) {
    if (cfg_.buttons) sim_.set_button_script(*cfg_.buttons);
    sim_.bring_up();  // the hand's device: forces written to it act on the grip from the first step
    silent_left_ = cfg_.faults.silent_handshakes;
    corrupt_left_ = cfg_.faults.corrupt_echo_loads;
    if (cfg_.firmware_loaded) mode_ = Mode::kRunning;
    if (!(std::isfinite(cfg_.encoder_noise_counts) && cfg_.encoder_noise_counts >= 0.0))
        throw Error("FalconEmulatorConfig.encoder_noise_counts = " + std::to_string(cfg_.encoder_noise_counts) +
                    " must be finite and >= 0");
    noise_rng_.seed(cfg_.noise_seed);
    pos_ = FalconKinematics::home_m();
    if (const auto a = kin_.inverse(pos_))
        for (int i = 0; i < 3; ++i)
            encoder_[i] = static_cast<std::int16_t>(kin_.theta_to_encoder((*a)[i].theta1) + cfg_.power_on_offset[i]);
}

void FalconEmulator::open() {
    if (gone_) return;  // a transport over an unplugged unit cannot open; the driver sees kNoDevice at once
    open_ = true;
}

void FalconEmulator::close() noexcept { open_ = false; }

TransferStatus FalconEmulator::control(const FtdiRequest& r, int) {
    if (gone_) return TransferStatus::kNoDevice;
    if (!open_ || r.request_type != 0x40) return TransferStatus::kError;
    switch (r.request) {
        case ftdi::kReset:
            if (r.value == ftdi::kPurgeRx || r.value == ftdi::kResetSio) in_.clear();
            if (r.value == ftdi::kPurgeTx || r.value == ftdi::kResetSio) partial_.clear();
            break;
        case ftdi::kModemCtrl:
            if (r.value == ftdi::kDtrLow) dtr_ = false;
            if (r.value == ftdi::kDtrHigh) {
                // A DTR edge at the handshake baud rate resets the microcontroller into its loader.
                if (!dtr_ && baud_ == ftdi::kBaud9600) {
                    mode_ = Mode::kHandshake;
                    homed_ = 0;
                    in_.clear();
                }
                dtr_ = true;
            }
            break;
        case ftdi::kBaudRate:
            baud_ = r.value;
            if (mode_ == Mode::kLoading && baud_ == ftdi::kBaudNormal && fw_bytes_ > 0) {
                mode_ = Mode::kRunning;
                ++loads_;
            }
            break;
        case ftdi::kLatencyTimer: latency_ = r.value; break;
        case ftdi::kFlowCtrl:
        case ftdi::kLineProps: break;
        default: return TransferStatus::kError;
    }
    return TransferStatus::kOk;
}

TransferStatus FalconEmulator::bulk_out(std::span<const std::uint8_t> data, int, std::size_t& written) {
    written = 0;
    if (gone_) return TransferStatus::kNoDevice;
    if (!open_) return TransferStatus::kError;
    written = data.size();
    switch (mode_) {
        case Mode::kLoader: break;  // no loader session: bytes are lost
        case Mode::kHandshake:
            if (baud_ == ftdi::kBaud9600 &&
                std::equal(data.begin(), data.end(), kHandshakeQuery.begin(), kHandshakeQuery.end())) {
                if (silent_left_ > 0) {
                    --silent_left_;
                } else {
                    in_.insert(in_.end(), kHandshakeReply.begin(), kHandshakeReply.end());
                    mode_ = Mode::kCheck;
                }
            }
            break;
        case Mode::kCheck:
            if (baud_ == ftdi::kBaudFirmware && !dtr_ && data.size() == 1 && data[0] == kLoaderCheck) {
                in_.push_back(kLoaderCheck);
                mode_ = Mode::kLoading;
                fw_bytes_ = 0;
                corrupt_this_load_ = corrupt_left_ > 0;
                if (corrupt_left_ > 0) --corrupt_left_;
            }
            break;
        case Mode::kLoading:
            for (const std::uint8_t b : data) {
                // The echo fault flips one bit of byte 100 (or the last byte of a shorter image).
                const bool flip = corrupt_this_load_ && fw_bytes_ == 100;
                in_.push_back(flip ? static_cast<std::uint8_t>(b ^ 0x10) : b);
                ++fw_bytes_;
            }
            break;
        case Mode::kRunning:
            if (baud_ != ftdi::kBaudNormal) break;  // at another baud rate the firmware reads noise: no answer
            for (const std::uint8_t b : data) {
                if (partial_.empty() && b != kFrameStart) continue;
                partial_.push_back(b);
                if (partial_.size() < kFrameBytes) continue;
                if (const auto c = decode_command(partial_))
                    on_command(*c);
                else
                    ++bad_commands_;
                partial_.clear();
            }
            break;
    }
    return TransferStatus::kOk;
}

TransferStatus FalconEmulator::bulk_in(std::span<std::uint8_t> packet, int, std::size_t& got) {
    got = 0;
    if (gone_) return TransferStatus::kNoDevice;
    if (!open_ || packet.size() < kModemBytes) return TransferStatus::kError;
    packet[0] = kModemIdle.modem;
    packet[1] = kModemIdle.line;
    const std::size_t n = std::min({in_.size(), packet.size() - kModemBytes, kUsbPacketBytes - kModemBytes});
    std::copy_n(in_.begin(), n, packet.begin() + kModemBytes);
    in_.erase(in_.begin(), in_.begin() + static_cast<std::ptrdiff_t>(n));
    got = kModemBytes + n;
    return TransferStatus::kOk;
}

TransferStatus FalconEmulator::exchange(std::span<const std::uint8_t> out, std::span<std::uint8_t> packet, int,
                                        std::size_t& got) {
    const auto t0 = std::chrono::steady_clock::now();
    got = 0;
    ++exchanges_;
    const FalconFaults& f = cfg_.faults;
    if (f.disconnect_at && exchanges_ >= f.disconnect_at) gone_ = true;
    if (gone_) return TransferStatus::kNoDevice;
    const std::size_t before = in_.size();
    std::size_t written = 0;
    TransferStatus s = bulk_out(out, 0, written);
    if (s != TransferStatus::kOk) return s;
    if (f.stall_at && exchanges_ >= f.stall_at && exchanges_ < f.stall_at + f.stall_exchanges) {
        in_.resize(before);  // the IN pipe stalls: the answer never comes
        last_exchange_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        return TransferStatus::kTimeout;
    }
    if (in_.size() >= before + kFrameBytes) {
        const std::size_t at = in_.size() - kFrameBytes;  // this exchange's state frame
        if (f.bad_framing_at == exchanges_) in_[at + kFrameBytes - 1] = 'x';
        if (f.bad_payload_at == exchanges_) in_[at + 5] = 0x20;
    }
    if (f.torn_frame_at == exchanges_ && in_.size() > kTornFirstBytes) {
        // Deliver only the first bytes now; the rest waits in the FIFO for the next IN packet.
        const std::size_t keep = std::min(packet.size(), kModemBytes + kTornFirstBytes);
        s = bulk_in(packet.first(keep), 0, got);
    } else {
        s = bulk_in(packet, 0, got);
    }
    last_exchange_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return s;
}

void FalconEmulator::on_command(const FalconCommand& c) {
    ++commands_;
    last_cmd_ = c;
    if (record_) log_.push_back(c);
    // The homing bit must be set in every command for the Falcon to stay homed (libnifalcon, FalconFirmware.h): a
    // command without it loses the homing, and the encoders count from the power-on offset again.
    if (!c.homing_mode && homed_ != 0) {
        homed_ = 0;
        pull_step_ = 0;
        ++homing_lost_;
    }
    const Vec3 home = FalconKinematics::home_m();
    if (homed_ != kAllHomed || (pull_step_ > 0 && pull_step_ < cfg_.homing_pull_exchanges)) {
        // Not homed (or the pull not finished): the hand rests at home, or pulls when the host asks for homing.
        force_ = Vec3(0.0);
        if (c.homing_mode || pull_step_ > 0) {
            ++pull_step_;
            const double phase =
                std::min(1.0, static_cast<double>(pull_step_) / std::max(1, cfg_.homing_pull_exchanges));
            const double out = cfg_.homing_pull_m * std::sin(kPi * phase);
            pos_ = home + Vec3(0.0, 0.0, out);
            // Motor i passes its index at (0.5 + 0.15 i) of the pull, on the way out.
            for (int i = 0; i < 3; ++i)
                if (phase <= 0.5 && out >= (0.5 + 0.15 * i) * cfg_.homing_pull_m)
                    homed_ |= static_cast<std::uint8_t>(1u << i);
            // Once every index has passed, the hand lets go and the grip settles back at home; a pull that ends
            // without all three (a short pull) is repeated while the host asks for homing.
            if (homed_ == kAllHomed) {
                pull_step_ = cfg_.homing_pull_exchanges;
                pos_ = home;
            } else if (phase >= 1.0) {
                pull_step_ = 0;
            }
        } else {
            pos_ = home;
        }
    } else {
        // Homed: the motors push on the hand's grip; the hand moves it along its path.
        const std::optional<Vec3> f = kin_.torque_to_force(pos_, command_to_torque(c.motor));
        force_ = f ? *f : Vec3(0.0);
        sim_.write(force_, Vec3(0.0));
        DeviceState st;
        sim_.read(st);
        pos_ = st.pose.position;
        grip_ = static_cast<std::uint8_t>(st.buttons & 0x0f);
    }
    if (const auto a = kin_.inverse(pos_))
        for (int i = 0; i < 3; ++i) {
            const int offset = (homed_ >> i) & 1 ? 0 : cfg_.power_on_offset[i];
            const int noise =
                cfg_.encoder_noise_counts > 0.0 ? static_cast<int>(std::lround(cfg_.encoder_noise_counts * noise_(noise_rng_))) : 0;
            encoder_[i] = static_cast<std::int16_t>(kin_.theta_to_encoder((*a)[i].theta1) + offset + noise);
        }
    queue_state();
}

void FalconEmulator::queue_state() {
    const Frame frame = encode_state(FalconState{encoder_, homed_, grip_});
    in_.insert(in_.end(), frame.begin(), frame.end());
    // A host that stops reading does not fill memory: the FTDI FIFO keeps the newest 4 frames.
    while (in_.size() > 4 * kFrameBytes) in_.pop_front();
}

}  // namespace tridex::devices::falcon
