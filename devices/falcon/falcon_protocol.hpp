// devices/falcon/falcon_protocol.hpp - the Novint Falcon's wire protocol as data: the FTDI bridge's vendor
// control requests and modem-status bytes, the firmware-load handshake, and the 16-byte framed packets.
//
// Source of every fact here: libnifalcon (Kyle Machulis, Nonpolynomial Labs, BSD; github.com/libnifalcon/libnifalcon),
// read for facts only: src/comm/FalconCommLibUSB.cpp (FTDI requests, handshake, endpoints, modem bytes),
// src/firmware/FalconFirmwareNovintSDK.cpp (packet layout), include/falcon/core/FalconFirmware.h (LED and
// homing bits), src/core/FalconFirmware.cpp (firmware load: 62-byte chunks, echo check, retries). The FTDI
// line-status bit meanings are from FTDI's FT232 data sheet (the second status byte of every IN packet).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace tridex::devices::falcon {

/// USB ids of the Falcon: FTDI's vendor id and Novint's product id on the FTDI bridge.
inline constexpr std::uint16_t kVendorId = 0x0403;
inline constexpr std::uint16_t kProductId = 0xcb48;
/// Bulk endpoints of the FTDI bridge (interface 0): OUT to the Falcon, IN from it.
inline constexpr std::uint8_t kEndpointOut = 0x02;
inline constexpr std::uint8_t kEndpointIn = 0x81;
/// Full-speed bulk packet size; every IN packet starts with kModemBytes status bytes, so it carries at most
/// 62 data bytes.
inline constexpr std::size_t kUsbPacketBytes = 64;
inline constexpr std::size_t kModemBytes = 2;
/// Firmware is written in chunks of this many bytes, each echoed back before the next (libnifalcon's READ_SIZE).
inline constexpr std::size_t kFirmwareChunkBytes = 62;

/// One FTDI vendor control request (bmRequestType 0x40, host to device, vendor, device recipient).
struct FtdiRequest {
    std::uint8_t request_type = 0x40;
    std::uint8_t request = 0;
    std::uint16_t value = 0;
    std::uint16_t index = 0;  ///< interface: 0 = any (the Falcon's bridge has one)
    bool operator==(const FtdiRequest&) const = default;
};

/// The FTDI requests (libftdi's SIO_* numbering, as libnifalcon uses them).
namespace ftdi {
inline constexpr std::uint8_t kReset = 0;         ///< SIO_RESET: value 0 reset, 1 purge RX, 2 purge TX
inline constexpr std::uint8_t kModemCtrl = 1;     ///< SIO_MODEM_CTRL: DTR/RTS
inline constexpr std::uint8_t kFlowCtrl = 2;      ///< SIO_SET_FLOW_CTRL: 0 = none
inline constexpr std::uint8_t kBaudRate = 3;      ///< SIO_SET_BAUD_RATE: value = divisor code
inline constexpr std::uint8_t kLineProps = 4;     ///< SIO_SET_DATA: bits | parity << 8 | stop << 11
inline constexpr std::uint8_t kLatencyTimer = 9;  ///< latency timer, ms

inline constexpr std::uint16_t kResetSio = 0, kPurgeRx = 1, kPurgeTx = 2;
/// Modem control values: the low byte sets the line, the high byte says which lines change.
inline constexpr std::uint16_t kDtrHigh = 0x0101, kDtrLow = 0x0100, kRtsHigh = 0x0202, kRtsLow = 0x0200;
/// Baud divisor codes: 9600 baud (handshake), about 140000 baud (firmware load), the fast normal mode.
inline constexpr std::uint16_t kBaud9600 = 0x4138, kBaudFirmware = 0x0015, kBaudNormal = 0x0002;
/// 8 data bits, no parity, 1 stop bit.
inline constexpr std::uint16_t kLine8N1 = 8;
/// Latency timer: 16 ms while loading firmware (shorter makes the handshake fail), 1 ms in normal mode.
inline constexpr std::uint16_t kLatencyFirmware = 16, kLatencyNormal = 1;

inline constexpr FtdiRequest request(std::uint8_t req, std::uint16_t value) { return FtdiRequest{0x40, req, value, 0}; }
}  // namespace ftdi

/// The control requests that put the bridge into firmware-load mode, in order, before the handshake: purge RX
/// and TX, latency 16 ms, 9600 baud, 8N1, no flow control, RTS low, DTR low then high (the DTR edge resets the
/// Falcon's microcontroller into its loader).
std::vector<FtdiRequest> firmware_mode_requests();
/// After the handshake: DTR low and the firmware-load baud rate; then the 'A' check.
std::vector<FtdiRequest> firmware_baud_requests();
/// Normal mode, after the firmware is loaded: latency 1 ms, the fast baud rate, purge RX and TX.
std::vector<FtdiRequest> normal_mode_requests();

/// The loader handshake: the host sends kHandshakeQuery; the loader answers kHandshakeReply (some hosts see a
/// leading 0x00 first: kHandshakeReplyLong). Then, at the firmware baud rate, the host sends kLoaderCheck and
/// the loader echoes it.
inline constexpr std::array<std::uint8_t, 3> kHandshakeQuery{0x0a, 0x43, 0x0d};
inline constexpr std::array<std::uint8_t, 4> kHandshakeReply{0x0a, 0x44, 0x2c, 0x0d};
inline constexpr std::array<std::uint8_t, 5> kHandshakeReplyLong{0x00, 0x0a, 0x44, 0x2c, 0x0d};
inline constexpr std::uint8_t kLoaderCheck = 0x41;  // 'A'
/// Handshake attempts before the load fails (libnifalcon tries 100 times).
inline constexpr int kHandshakeAttempts = 100;

/// The two FTDI status bytes at the start of every IN packet.
struct ModemStatus {
    std::uint8_t modem = 0;  ///< CTS 0x10, DSR 0x20, RI 0x40, DCD 0x80 (low nibble reserved)
    std::uint8_t line =
        0;  ///< line status: overrun 0x02, parity 0x04, framing 0x08, break 0x10, THRE 0x20, TEMT 0x40, FIFO error 0x80
    /// True when the line status reports a receive error (overrun, parity, framing, break or FIFO error).
    bool line_error() const { return (line & 0x9e) != 0; }
};
/// What an idle FT232 typically sends: CTS | DSR with the reserved bit set, and transmitter empty.
inline constexpr ModemStatus kModemIdle{0x31, 0x60};

/// LED bits of the command packet (FalconFirmware.h).
enum FalconLed : std::uint8_t { kLedGreen = 0x02, kLedBlue = 0x04, kLedRed = 0x08 };
/// The homing-mode bit of the command packet.
inline constexpr std::uint8_t kHomingModeBit = 0x01;
/// Homing-status bits of the state packet: one per motor.
inline constexpr std::uint8_t kAllHomed = 0x07;

/// A frame is kFrameBytes long: '<', 14 payload bytes each offset by 0x41 ('A'), '>'.
inline constexpr std::size_t kFrameBytes = 16;
inline constexpr std::uint8_t kFrameStart = '<', kFrameEnd = '>', kNibbleBase = 0x41;
using Frame = std::array<std::uint8_t, kFrameBytes>;

/// Host -> Falcon, once per tick.
struct FalconCommand {
    std::array<std::int16_t, 3> motor{0, 0, 0};  ///< motor commands, firmware units (16-bit signed)
    std::uint8_t leds = 0;                       ///< FalconLed bits
    bool homing_mode = false;                    ///< ask the firmware to home the encoders
    bool operator==(const FalconCommand&) const = default;
};

/// Falcon -> host, once per tick.
struct FalconState {
    std::array<std::int16_t, 3> encoder{0, 0, 0};  ///< encoder counts (16-bit signed)
    std::uint8_t homing_status = 0;                ///< bit i: motor i homed
    std::uint8_t grip_buttons = 0;                 ///< 4 grip buttons, bit i = button i
    bool operator==(const FalconState&) const = default;
};

/// Encodes a command: byte 0 '<'; bytes 1..12 the three motors, 4 nibbles each, least significant first, each
/// nibble + 0x41; byte 13 (leds | homing bit) + 0x41; byte 14 0x41; byte 15 '>'.
Frame encode_command(const FalconCommand& c);
/// Decodes a command frame (the emulator's side); nullopt when the framing bytes or a nibble are wrong.
std::optional<FalconCommand> decode_command(std::span<const std::uint8_t> frame);
/// Encodes a state: '<'; encoders as 4 nibbles each + 0x41; byte 13 = (homing_status << 4 | grip) + 0x41;
/// byte 14 0x41; '>'.
Frame encode_state(const FalconState& s);
/// Decodes a state frame; nullopt when it is not exactly '<' + 14 payload bytes in 0x41..0xc0 + '>'. Bits above
/// the nibbles are checked: byte 13 carries 3 homing bits and 4 grip bits.
std::optional<FalconState> decode_state(std::span<const std::uint8_t> frame);

/// Reassembles state frames from the IN stream (data bytes after the modem bytes): bytes before a '<' are
/// skipped, a '<' ... '>' of 16 bytes is a frame; a '>' too early, a '<' inside a frame (the partial one is
/// dropped) or a bad payload byte makes a malformed frame. Holds at most one
/// partial frame (a frame torn across two USB packets is completed by the next packet).
class StateFramer {
public:
    /// Feeds data bytes; returns the newest complete, well-formed state in them (older ones are dropped) and
    /// counts malformed frames.
    std::optional<FalconState> feed(std::span<const std::uint8_t> data);
    /// Malformed frames seen (bad framing byte or payload).
    std::uint64_t malformed() const { return malformed_; }
    /// Bytes of a partial frame waiting for the next packet.
    std::size_t pending() const { return n_; }
    /// Drops a partial frame.
    void reset() { n_ = 0; }

private:
    Frame buf_{};
    std::size_t n_ = 0;
    std::uint64_t malformed_ = 0;
};

/// Splits an IN packet into its modem status and data bytes; nullopt when shorter than the status bytes.
std::optional<ModemStatus> split_in_packet(std::span<const std::uint8_t> packet, std::span<const std::uint8_t>& data);

}  // namespace tridex::devices::falcon
