// devices/falcon/falcon_firmware.hpp - loading the Falcon's firmware over its FTDI bridge, and checking that it
// runs. The sequence is libnifalcon's (src/comm/FalconCommLibUSB.cpp setFirmwareMode/setNormalMode,
// src/core/FalconFirmware.cpp loadFirmware/isFirmwareLoaded), read for facts:
//   1. firmware mode: purge, latency 16 ms, 9600 baud 8N1, no flow control, RTS low, DTR low -> high;
//   2. handshake: send 0a 43 0d until the loader answers 0a 44 2c 0d (up to 100 tries);
//   3. DTR low, the firmware baud rate, send 'A', expect 'A' back;
//   4. the image in 62-byte chunks, each echoed back byte for byte before the next (the echo check);
//   5. normal mode: latency 1 ms, the fast baud rate, purge.
// A failed attempt (no handshake, a wrong echo, a timeout) is retried from step 1.
//
// The firmware is Novint's and tridex never ships it: the user names a file from their own installation.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "devices/falcon/falcon_transport.hpp"

namespace tridex::devices::falcon {

/// How hard to try.
struct FirmwareLoadOptions {
    int attempts = 3;                          ///< whole-sequence attempts (1..100)
    int handshake_tries = kHandshakeAttempts;  ///< handshake queries per attempt
    int timeout_ms = 1000;                     ///< per transfer
    int empty_reads = 50;                      ///< IN packets with no echo data tolerated per chunk before it times out
};

/// What a load did.
struct FirmwareLoadReport {
    bool ok = false;
    int attempts = 0;            ///< attempts made
    int echo_mismatches = 0;     ///< attempts that failed the echo check
    int handshake_failures = 0;  ///< attempts whose handshake never answered
    std::size_t bytes = 0;       ///< image size
    std::string error;           ///< why the last attempt failed ("" when ok)
};

/// Loads `image` (never empty) through `transport` (open). Never throws; the report says what happened. A gone
/// device (kNoDevice) ends the load at once.
FirmwareLoadReport load_firmware(FalconTransport& transport, std::span<const std::uint8_t> image,
                                 const FirmwareLoadOptions& options = {});

/// Puts the FTDI bridge in normal mode (normal_mode_requests: latency 1 ms, the fast baud rate, purge), as
/// libnifalcon's FalconCommLibUSB::open does before anything is asked of the firmware. False with `error` set when
/// a request fails or the Falcon is gone. Never throws.
bool set_normal_mode(FalconTransport& transport, int timeout_ms, std::string& error);

/// True when firmware answers: up to `tries` exchanges of a zero command, each returning a well-formed state frame
/// counted (libnifalcon's isFirmwareLoaded). The bridge must be in normal mode (set_normal_mode).
bool firmware_running(FalconTransport& transport, int tries = 10, int timeout_us = 20000);

/// The one line a user sees when the firmware is needed and not given.
std::string firmware_missing_message();

/// Reads a firmware file; throws tridex::Error with one line naming the file (missing, unreadable, empty, or
/// larger than 64 KiB, which no Falcon image is).
std::vector<std::uint8_t> read_firmware_file(const std::string& path);

/// A dummy image for the emulator: 1 KiB of a fixed pseudo-random pattern, generated here. It is not firmware and
/// means nothing to a real Falcon; the emulator accepts any bytes as firmware.
std::vector<std::uint8_t> emulator_firmware_image();

}  // namespace tridex::devices::falcon
