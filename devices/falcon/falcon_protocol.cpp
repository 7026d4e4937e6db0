// devices/falcon/falcon_protocol.cpp - packet encode/decode and the FTDI request sequences (libnifalcon's facts).
#include "devices/falcon/falcon_protocol.hpp"

namespace tridex::devices::falcon {

namespace {

// Four nibbles of v, least significant first, each + 0x41, at out[at..at+3].
void put_word(Frame& out, std::size_t at, std::int16_t v) {
    const auto u = static_cast<std::uint16_t>(v);
    for (int k = 0; k < 4; ++k) out[at + k] = static_cast<std::uint8_t>(((u >> (4 * k)) & 0xf) + kNibbleBase);
}

// The word at frame[at..at+3]; false when a byte is not a nibble + 0x41.
bool get_word(std::span<const std::uint8_t> f, std::size_t at, std::int16_t& v) {
    std::uint16_t u = 0;
    for (int k = 0; k < 4; ++k) {
        const int n = static_cast<int>(f[at + k]) - kNibbleBase;
        if (n < 0 || n > 15) return false;
        u = static_cast<std::uint16_t>(u | (n << (4 * k)));
    }
    v = static_cast<std::int16_t>(u);
    return true;
}

bool framed(std::span<const std::uint8_t> f) {
    return f.size() == kFrameBytes && f[0] == kFrameStart && f[kFrameBytes - 1] == kFrameEnd;
}

}  // namespace

std::vector<FtdiRequest> firmware_mode_requests() {
    using namespace ftdi;
    return {request(kReset, kPurgeRx),     request(kReset, kPurgeTx),     request(kLatencyTimer, kLatencyFirmware),
            request(kBaudRate, kBaud9600), request(kLineProps, kLine8N1), request(kFlowCtrl, 0),
            request(kModemCtrl, kRtsLow),  request(kModemCtrl, kDtrLow),  request(kModemCtrl, kDtrHigh)};
}

std::vector<FtdiRequest> firmware_baud_requests() {
    using namespace ftdi;
    return {request(kModemCtrl, kDtrLow), request(kBaudRate, kBaudFirmware)};
}

std::vector<FtdiRequest> normal_mode_requests() {
    using namespace ftdi;
    return {request(kLatencyTimer, kLatencyNormal), request(kBaudRate, kBaudNormal), request(kReset, kPurgeRx),
            request(kReset, kPurgeTx)};
}

Frame encode_command(const FalconCommand& c) {
    Frame f{};
    f[0] = kFrameStart;
    for (int i = 0; i < 3; ++i) put_word(f, 1 + 4 * i, c.motor[i]);
    f[13] = static_cast<std::uint8_t>(
        ((c.leds & (kLedGreen | kLedBlue | kLedRed)) | (c.homing_mode ? kHomingModeBit : 0)) + kNibbleBase);
    f[14] = kNibbleBase;
    f[15] = kFrameEnd;
    return f;
}

std::optional<FalconCommand> decode_command(std::span<const std::uint8_t> frame) {
    if (!framed(frame)) return std::nullopt;
    FalconCommand c;
    for (int i = 0; i < 3; ++i)
        if (!get_word(frame, 1 + 4 * i, c.motor[i])) return std::nullopt;
    const int b = static_cast<int>(frame[13]) - kNibbleBase;
    if (b < 0 || b > 15 || frame[14] != kNibbleBase) return std::nullopt;
    c.leds = static_cast<std::uint8_t>(b & (kLedGreen | kLedBlue | kLedRed));
    c.homing_mode = (b & kHomingModeBit) != 0;
    return c;
}

Frame encode_state(const FalconState& s) {
    Frame f{};
    f[0] = kFrameStart;
    for (int i = 0; i < 3; ++i) put_word(f, 1 + 4 * i, s.encoder[i]);
    f[13] = static_cast<std::uint8_t>((((s.homing_status & kAllHomed) << 4) | (s.grip_buttons & 0x0f)) + kNibbleBase);
    f[14] = kNibbleBase;
    f[15] = kFrameEnd;
    return f;
}

std::optional<FalconState> decode_state(std::span<const std::uint8_t> frame) {
    if (!framed(frame)) return std::nullopt;
    FalconState s;
    for (int i = 0; i < 3; ++i)
        if (!get_word(frame, 1 + 4 * i, s.encoder[i])) return std::nullopt;
    const int b = static_cast<int>(frame[13]) - kNibbleBase;
    if (b < 0 || b > 0x7f) return std::nullopt;
    const int b14 = static_cast<int>(frame[14]) - kNibbleBase;
    if (b14 < 0 || b14 > 15) return std::nullopt;
    s.homing_status = static_cast<std::uint8_t>((b >> 4) & kAllHomed);
    s.grip_buttons = static_cast<std::uint8_t>(b & 0x0f);
    return s;
}

std::optional<FalconState> StateFramer::feed(std::span<const std::uint8_t> data) {
    std::optional<FalconState> newest;
    for (const std::uint8_t byte : data) {
        if (n_ == 0 && byte != kFrameStart) continue;  // skip to the next frame start
        if (n_ > 0 && byte == kFrameStart) {           // a new frame starts inside a partial one: the partial is lost
            ++malformed_;
            n_ = 0;
        }
        buf_[n_++] = byte;
        if (n_ < kFrameBytes && byte != kFrameEnd) continue;
        if (n_ == kFrameBytes) {
            if (auto s = decode_state(buf_))
                newest = s;
            else
                ++malformed_;
        } else {
            ++malformed_;  // a '>' before 16 bytes: a short or corrupted frame
        }
        n_ = 0;
    }
    return newest;
}

std::optional<ModemStatus> split_in_packet(std::span<const std::uint8_t> packet, std::span<const std::uint8_t>& data) {
    if (packet.size() < kModemBytes) return std::nullopt;
    data = packet.subspan(kModemBytes);
    return ModemStatus{packet[0], packet[1]};
}

}  // namespace tridex::devices::falcon
