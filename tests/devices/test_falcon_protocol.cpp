// tests/devices/test_falcon_protocol.cpp - Falcon packets against hand-computed bytes; the framer; FTDI requests.
#include <gtest/gtest.h>

#include <vector>

#include "devices/falcon/falcon_protocol.hpp"

namespace tridex::devices::falcon {
namespace {

std::vector<std::uint8_t> bytes(const Frame& f) { return {f.begin(), f.end()}; }

TEST(FalconProtocol, CommandMatchesHandComputedBytes) {
    // Motor 0 = 0x1234: nibbles 4, 3, 2, 1 (least significant first) + 0x41 = 'E', 'D', 'C', 'B'.
    // Motor 1 = -1 = 0xffff: four 0xf + 0x41 = 'P'. Motor 2 = 0: four 'A'.
    // Byte 13: green (0x02) | homing (0x01) = 0x03 + 0x41 = 'D'; byte 14 'A'.
    FalconCommand c;
    c.motor = {0x1234, -1, 0};
    c.leds = kLedGreen;
    c.homing_mode = true;
    const std::vector<std::uint8_t> want{'<', 'E', 'D', 'C', 'B', 'P', 'P', 'P',
                                         'P', 'A', 'A', 'A', 'A', 'D', 'A', '>'};
    EXPECT_EQ(bytes(encode_command(c)), want);
    const auto back = decode_command(want);
    ASSERT_TRUE(back);
    EXPECT_EQ(*back, c);
    // All LEDs, no homing: 0x0e + 0x41 = 0x4f 'O'.
    c = FalconCommand{{-32768, 32767, 1}, kLedRed | kLedBlue | kLedGreen, false};
    const Frame f = encode_command(c);
    EXPECT_EQ(f[13], 'O');
    EXPECT_EQ((std::vector<std::uint8_t>(f.begin() + 1, f.begin() + 5)),
              (std::vector<std::uint8_t>{'A', 'A', 'A', 'I'}));  // 0x8000
    EXPECT_EQ(*decode_command(f), c);
}

TEST(FalconProtocol, StateMatchesHandComputedBytes) {
    // Encoders 0x00ff ('P','P','A','A'), -2 = 0xfffe ('O','P','P','P'), 0x0100 ('A','A','B','A'); homing 0b101,
    // grip 0b0011: byte 13 = 0x53 + 0x41 = 0x94.
    const std::vector<std::uint8_t> wire{'<', 'P', 'P', 'A', 'A', 'O',  'P', 'P',
                                         'P', 'A', 'A', 'B', 'A', 0x94, 'A', '>'};
    const auto s = decode_state(wire);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->encoder[0], 0x00ff);
    EXPECT_EQ(s->encoder[1], -2);
    EXPECT_EQ(s->encoder[2], 0x0100);
    EXPECT_EQ(s->homing_status, 0b101);
    EXPECT_EQ(s->grip_buttons, 0b0011);
    EXPECT_EQ(bytes(encode_state(*s)), wire);
}

TEST(FalconProtocol, RefusesBadFramingAndPayload) {
    Frame f = encode_state(FalconState{{1, 2, 3}, 7, 0});
    EXPECT_TRUE(decode_state(f));
    Frame g = f;
    g[0] = 'x';
    EXPECT_FALSE(decode_state(g));
    g = f;
    g[15] = 'x';
    EXPECT_FALSE(decode_state(g));
    g = f;
    g[3] = 0x20;  // below 'A'
    EXPECT_FALSE(decode_state(g));
    EXPECT_FALSE(decode_state(std::vector<std::uint8_t>(f.begin(), f.begin() + 15)));
    Frame c = encode_command(FalconCommand{});
    c[14] = 'B';
    EXPECT_FALSE(decode_command(c));
}

TEST(FalconProtocol, FramerReassemblesTornFramesAndCountsMalformedOnes) {
    StateFramer fr;
    const Frame a = encode_state(FalconState{{10, 20, 30}, 7, 1});
    const Frame b = encode_state(FalconState{{11, 21, 31}, 7, 2});
    // Garbage, then a frame torn 7 + 9 bytes.
    std::vector<std::uint8_t> first{0x00, 0x13};
    first.insert(first.end(), a.begin(), a.begin() + 7);
    EXPECT_FALSE(fr.feed(first));
    EXPECT_EQ(fr.pending(), 7u);
    std::vector<std::uint8_t> second(a.begin() + 7, a.end());
    second.insert(second.end(), b.begin(), b.end());
    const auto s = fr.feed(second);  // the newest of the two
    ASSERT_TRUE(s);
    EXPECT_EQ(s->encoder[0], 11);
    EXPECT_EQ(fr.malformed(), 0u);
    // A frame with its '>' replaced: malformed; a short frame ending early with '>': malformed.
    Frame bad = a;
    bad[15] = 'x';
    EXPECT_FALSE(fr.feed(bad));
    EXPECT_EQ(fr.malformed(), 1u);
    const std::vector<std::uint8_t> shortf{'<', 'A', 'A', '>'};
    EXPECT_FALSE(fr.feed(shortf));
    EXPECT_EQ(fr.malformed(), 2u);
    // A torn frame followed by a fresh one: the partial is dropped, the fresh one decodes.
    std::vector<std::uint8_t> mixed(a.begin(), a.begin() + 5);
    mixed.insert(mixed.end(), b.begin(), b.end());
    ASSERT_TRUE(fr.feed(mixed));
    EXPECT_EQ(fr.malformed(), 3u);
}

TEST(FalconProtocol, ModemBytesAndFtdiRequests) {
    const std::vector<std::uint8_t> packet{0x31, 0x60, '<'};
    std::span<const std::uint8_t> data;
    const auto m = split_in_packet(packet, data);
    ASSERT_TRUE(m);
    EXPECT_EQ(m->modem, 0x31);
    EXPECT_FALSE(m->line_error());
    EXPECT_EQ(data.size(), 1u);
    EXPECT_TRUE((ModemStatus{0x31, 0x62}).line_error());  // overrun
    EXPECT_FALSE(split_in_packet(std::vector<std::uint8_t>{0x31}, data));
    // libnifalcon's firmware-mode sequence: purge RX, purge TX, latency 16, 9600 baud (0x4138), 8N1, no flow, RTS
    // low, DTR low, DTR high; all vendor OUT requests (0x40) to interface 0.
    const auto fw = firmware_mode_requests();
    ASSERT_EQ(fw.size(), 9u);
    EXPECT_EQ(fw[0], (FtdiRequest{0x40, 0, 1, 0}));
    EXPECT_EQ(fw[1], (FtdiRequest{0x40, 0, 2, 0}));
    EXPECT_EQ(fw[2], (FtdiRequest{0x40, 9, 16, 0}));
    EXPECT_EQ(fw[3], (FtdiRequest{0x40, 3, 0x4138, 0}));
    EXPECT_EQ(fw[4], (FtdiRequest{0x40, 4, 8, 0}));
    EXPECT_EQ(fw[5], (FtdiRequest{0x40, 2, 0, 0}));
    EXPECT_EQ(fw[6], (FtdiRequest{0x40, 1, 0x0200, 0}));
    EXPECT_EQ(fw[7], (FtdiRequest{0x40, 1, 0x0100, 0}));
    EXPECT_EQ(fw[8], (FtdiRequest{0x40, 1, 0x0101, 0}));
    EXPECT_EQ(firmware_baud_requests()[1], (FtdiRequest{0x40, 3, 0x15, 0}));
    const auto normal = normal_mode_requests();
    EXPECT_EQ(normal[0], (FtdiRequest{0x40, 9, 1, 0}));
    EXPECT_EQ(normal[1], (FtdiRequest{0x40, 3, 2, 0}));
}

}  // namespace
}  // namespace tridex::devices::falcon
