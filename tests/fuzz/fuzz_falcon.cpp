// tests/fuzz/fuzz_falcon.cpp - libFuzzer target: the Novint Falcon's protocol decoding as FalconDevice runs it.
// The input is a stream of USB IN packets, each a length byte (taken modulo 65) and that many bytes (two modem
// status bytes, then data): split_in_packet, then one StateFramer across the packets. Each 16 bytes are also
// decoded as a command frame (the emulator's side). Nothing here throws; a decoded state or command must encode
// back to the frame it came from.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <span>

#include "devices/falcon/falcon_protocol.hpp"

namespace falcon = tridex::devices::falcon;

namespace {

/// Aborts (a finding) unless `frame` re-encodes to itself through decode_command / encode_command.
void check_command_frame(std::span<const std::uint8_t> frame) {
    const std::optional<falcon::FalconCommand> c = falcon::decode_command(frame);
    if (!c) return;
    const falcon::Frame again = falcon::encode_command(*c);
    if (std::equal(again.begin(), again.end(), frame.begin())) return;
    std::fprintf(stderr, "tridex fuzz: a decoded Falcon command does not encode back to its frame\n");
    std::abort();
}

}  // namespace

/// One fuzz input as a stream of IN packets.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    falcon::StateFramer framer;
    std::size_t at = 0;
    while (at < size) {
        const std::size_t n = std::min<std::size_t>(data[at] % (falcon::kUsbPacketBytes + 1), size - at - 1);
        const std::span<const std::uint8_t> packet(data + at + 1, n);
        at += 1 + n;
        std::span<const std::uint8_t> payload;
        if (!falcon::split_in_packet(packet, payload)) continue;
        const std::optional<falcon::FalconState> s = framer.feed(payload);
        if (s && falcon::decode_state(falcon::encode_state(*s)) != s) {
            std::fprintf(stderr, "tridex fuzz: a Falcon state does not survive encode_state / decode_state\n");
            std::abort();
        }
        if (framer.pending() >= falcon::kFrameBytes) {
            std::fprintf(stderr, "tridex fuzz: the Falcon framer holds %zu bytes\n", framer.pending());
            std::abort();
        }
    }
    for (std::size_t k = 0; k + falcon::kFrameBytes <= size; k += falcon::kFrameBytes)
        check_command_frame(std::span<const std::uint8_t>(data + k, falcon::kFrameBytes));
    return 0;
}
