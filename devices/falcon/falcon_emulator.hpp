// devices/falcon/falcon_emulator.hpp - a Novint Falcon in memory, behind the driver's transport interface, with a
// fault injector. It speaks the protocol of falcon_protocol.hpp: the FTDI modem bytes on every IN packet, the
// control requests, the loader's handshake and 'A' check, the firmware echo, then one state frame per command
// frame. Its grip is held by the simulated hand of devices/simulated_device.hpp (the same closed-loop hand and
// scripted path the `simulated` driver uses), with the Falcon profile; the motor commands act on it as forces
// F = G^T tau (falcon_kinematics.hpp), and the encoders report the quantised motor angles of the inverse kinematics
// of the grip's position. Homing: until the host sets the homing bit, the encoders count from an arbitrary
// power-on offset; with it set, a scripted grip pull (out toward the user) passes each motor's index, which sets
// that motor's homing bit and removes its offset; when all three are homed the grip settles back at home. A command
// without the homing bit loses the homing again (libnifalcon's FalconFirmware.h: the bit must be set in every
// command for the Falcon to stay homed).
// Deterministic: time advances one period per command frame, whatever the wall clock.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "devices/button_script.hpp"
#include "devices/falcon/falcon_kinematics.hpp"
#include "devices/falcon/falcon_transport.hpp"
#include "devices/scripted_path.hpp"
#include "devices/simulated_device.hpp"

namespace tridex::devices::falcon {

/// Faults to inject; 0 disables each. Exchanges are counted from 1 over the whole life of the emulator (the
/// driver's probes and homing count too: exchanges() says how many happened so far).
struct FalconFaults {
    int silent_handshakes = 0;         ///< the loader ignores this many handshake queries
    int corrupt_echo_loads = 0;        ///< this many firmware loads get one echoed byte flipped
    std::uint64_t torn_frame_at = 0;   ///< this exchange's state frame comes in two pieces: 7 bytes now, 9 next time
    std::uint64_t bad_framing_at = 0;  ///< this exchange's state frame has its closing '>' replaced
    std::uint64_t bad_payload_at = 0;  ///< this exchange's state frame has a payload byte out of range
    std::uint64_t stall_at = 0;        ///< from this exchange on, stall_exchanges exchanges return no data (a stall)
    std::uint64_t stall_exchanges = 0;
    std::uint64_t disconnect_at = 0;  ///< from this exchange on, the device is gone (unplugged mid-session)
};

/// The emulated unit.
struct FalconEmulatorConfig {
    /// The hand's target path in the device frame (m); default: hold the grip at home.
    std::optional<ScriptedPath> hand_path;
    std::optional<ButtonScript> buttons;  ///< grip buttons (bits 0..3), in device time
    SimulatedHandParams hand{};           ///< the simulated hand (mass, stiffness, damping)
    double period_s = 1e-3;               ///< device time per command frame
    bool firmware_loaded = false;         ///< true: powered up with firmware running (as after an earlier session)
    std::array<std::int16_t, 3> power_on_offset{1234, -777, 321};  ///< encoder counts before homing, per motor
    double homing_pull_m = 0.03;                                   ///< the scripted pull: out along +z by this much ...
    int homing_pull_exchanges = 300;                               ///< ... and back, over this many command frames
    FalconFaults faults{};
    /// Sensor noise: standard deviation of white Gaussian noise added to each encoder reading, counts (>= 0; 0 = off,
    /// the default, so the encoders are exactly the inverse kinematics' quantised angles).
    double encoder_noise_counts = 0.0;
    std::uint32_t noise_seed = 1;  ///< seed of that noise
};

/// In-memory Falcon; single-threaded like every transport. Inspection accessors are for tests.
class FalconEmulator : public FalconTransport {
public:
    explicit FalconEmulator(FalconEmulatorConfig config = {});

    void open() override;
    void close() noexcept override;
    TransferStatus control(const FtdiRequest& request, int timeout_ms) override;
    TransferStatus bulk_out(std::span<const std::uint8_t> data, int timeout_ms, std::size_t& written) override;
    TransferStatus bulk_in(std::span<std::uint8_t> packet, int timeout_ms, std::size_t& got) override;
    TransferStatus exchange(std::span<const std::uint8_t> out, std::span<std::uint8_t> packet, int timeout_us,
                            std::size_t& got) override;
    bool unplugged() const override { return gone_; }
    double last_exchange_s() const override { return last_exchange_s_; }
    std::string describe() const override { return "Falcon emulator"; }

    /// Replaces the faults (between exchanges).
    void set_faults(const FalconFaults& f) { cfg_.faults = f; }
    /// Pulls the plug now.
    void unplug() { gone_ = true; }

    bool firmware_loaded() const { return mode_ == Mode::kRunning; }
    int firmware_loads() const { return loads_; }             ///< firmware loads completed
    std::size_t firmware_bytes() const { return fw_bytes_; }  ///< bytes of the last load
    std::uint64_t exchanges() const { return exchanges_; }
    std::uint64_t command_frames() const { return commands_; }
    std::uint64_t malformed_commands() const { return bad_commands_; }
    /// The last command frame received (motor commands, LEDs, homing bit).
    const FalconCommand& last_command() const { return last_cmd_; }
    /// Every command frame's motor commands (kept when record_commands(true)).
    void record_commands(bool on) { record_ = on; }
    const std::vector<FalconCommand>& commands() const { return log_; }
    std::uint8_t homing_status() const { return homed_; }
    /// Times a command without the homing bit undid the homing (the host dropped the bit after homing).
    int homing_lost() const { return homing_lost_; }
    /// The grip's true position (m) and the force the motors applied on the last step (N).
    const Vec3& position_m() const { return pos_; }
    const Vec3& applied_force_n() const { return force_; }
    const FalconKinematics& kinematics() const { return kin_; }

private:
    enum class Mode { kLoader, kHandshake, kCheck, kLoading, kRunning };
    void on_command(const FalconCommand& c);
    void queue_state();

    FalconEmulatorConfig cfg_;
    FalconKinematics kin_;
    SimulatedDevice sim_;
    Mode mode_ = Mode::kLoader;
    bool gone_ = false, open_ = false, record_ = false;
    std::uint16_t baud_ = 0, latency_ = 16;
    bool dtr_ = false;
    int silent_left_ = 0, corrupt_left_ = 0;
    bool corrupt_this_load_ = false;
    int loads_ = 0;
    std::size_t fw_bytes_ = 0;
    std::deque<std::uint8_t> in_;        // data bytes waiting for the host
    std::vector<std::uint8_t> partial_;  // command bytes of a frame not complete yet
    std::uint64_t exchanges_ = 0, commands_ = 0, bad_commands_ = 0;
    std::uint64_t stall_left_ = 0;
    FalconCommand last_cmd_{};
    std::vector<FalconCommand> log_;
    std::uint8_t homed_ = 0;
    int pull_step_ = 0;
    int homing_lost_ = 0;
    Vec3 pos_{0.0}, force_{0.0};
    std::array<std::int16_t, 3> encoder_{0, 0, 0};
    std::mt19937 noise_rng_{1};
    std::normal_distribution<double> noise_{0.0, 1.0};
    std::uint8_t grip_ = 0;
    double last_exchange_s_ = 0.0;
};

}  // namespace tridex::devices::falcon
