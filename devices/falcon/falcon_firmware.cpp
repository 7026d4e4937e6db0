// devices/falcon/falcon_firmware.cpp - the firmware load sequence with its echo check and retries.
#include "devices/falcon/falcon_firmware.hpp"

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"

namespace tridex::devices::falcon {

namespace {

enum class Step { kOk, kFailed, kGone };

Step requests(FalconTransport& t, const std::vector<FtdiRequest>& list, int timeout_ms, std::string& error) {
    for (const FtdiRequest& r : list) {
        const TransferStatus s = t.control(r, timeout_ms);
        if (s == TransferStatus::kNoDevice) return error = "the Falcon was unplugged", Step::kGone;
        if (s != TransferStatus::kOk) {
            error = "FTDI request " + std::to_string(r.request) + " failed (" + to_string(s) + ")";
            return Step::kFailed;
        }
    }
    return Step::kOk;
}

Step write_all(FalconTransport& t, std::span<const std::uint8_t> data, int timeout_ms, std::string& error) {
    std::size_t written = 0;
    const TransferStatus s = t.bulk_out(data, timeout_ms, written);
    if (s == TransferStatus::kNoDevice) return error = "the Falcon was unplugged", Step::kGone;
    if (s != TransferStatus::kOk || written != data.size())
        return error = std::string("bulk write ") + to_string(s), Step::kFailed;
    return Step::kOk;
}

// One IN packet's data bytes into `data` (cleared first).
Step read_data(FalconTransport& t, int timeout_ms, std::vector<std::uint8_t>& data, std::string& error) {
    std::array<std::uint8_t, kUsbPacketBytes> packet{};
    std::size_t got = 0;
    data.clear();
    const TransferStatus s = t.bulk_in(packet, timeout_ms, got);
    if (s == TransferStatus::kNoDevice) return error = "the Falcon was unplugged", Step::kGone;
    if (s == TransferStatus::kTimeout) return Step::kOk;  // nothing came: the caller counts empty reads
    if (s != TransferStatus::kOk) return error = std::string("bulk read ") + to_string(s), Step::kFailed;
    std::span<const std::uint8_t> bytes;
    if (split_in_packet(std::span<const std::uint8_t>(packet.data(), got), bytes))
        data.assign(bytes.begin(), bytes.end());
    return Step::kOk;
}

Step handshake(FalconTransport& t, const FirmwareLoadOptions& o, std::string& error) {
    std::vector<std::uint8_t> data;
    for (int i = 0; i < o.handshake_tries; ++i) {
        if (Step s = write_all(t, kHandshakeQuery, o.timeout_ms, error); s != Step::kOk) return s;
        if (Step s = read_data(t, o.timeout_ms, data, error); s != Step::kOk) return s;
        if (std::equal(data.begin(), data.end(), kHandshakeReply.begin(), kHandshakeReply.end()) ||
            std::equal(data.begin(), data.end(), kHandshakeReplyLong.begin(), kHandshakeReplyLong.end()))
            return Step::kOk;
    }
    error = "the Falcon's loader did not answer the handshake (" + std::to_string(o.handshake_tries) + " tries)";
    return Step::kFailed;
}

Step loader_check(FalconTransport& t, const FirmwareLoadOptions& o, std::string& error) {
    const std::array<std::uint8_t, 1> a{kLoaderCheck};
    if (Step s = write_all(t, a, o.timeout_ms, error); s != Step::kOk) return s;
    std::vector<std::uint8_t> data;
    for (int i = 0; i < o.empty_reads && data.empty(); ++i)
        if (Step s = read_data(t, o.timeout_ms, data, error); s != Step::kOk) return s;
    if (data.size() != 1 || data[0] != kLoaderCheck) return error = "the loader did not echo 'A'", Step::kFailed;
    return Step::kOk;
}

// Writes the image chunk by chunk; each chunk's echo must come back byte for byte before the next is sent.
Step send_image(FalconTransport& t, std::span<const std::uint8_t> image, const FirmwareLoadOptions& o, bool& mismatch,
                std::string& error) {
    std::vector<std::uint8_t> data;
    for (std::size_t at = 0; at < image.size(); at += kFirmwareChunkBytes) {
        const std::span<const std::uint8_t> chunk = image.subspan(at, std::min(kFirmwareChunkBytes, image.size() - at));
        if (Step s = write_all(t, chunk, o.timeout_ms, error); s != Step::kOk) return s;
        std::size_t echoed = 0;
        int empty = 0;
        while (echoed < chunk.size()) {
            if (Step s = read_data(t, o.timeout_ms, data, error); s != Step::kOk) return s;
            if (data.empty()) {
                if (++empty > o.empty_reads) {
                    error = "no echo of firmware byte " + std::to_string(at + echoed);
                    return Step::kFailed;
                }
                continue;
            }
            for (std::size_t k = 0; k < data.size(); ++k) {
                if (echoed + k >= chunk.size() || data[k] != chunk[echoed + k]) {
                    mismatch = true;
                    error = "firmware echo mismatch at byte " + std::to_string(at + echoed + k);
                    return Step::kFailed;
                }
            }
            echoed += data.size();
        }
    }
    return Step::kOk;
}

}  // namespace

const char* to_string(TransferStatus s) {
    switch (s) {
        case TransferStatus::kOk: return "ok";
        case TransferStatus::kTimeout: return "timeout";
        case TransferStatus::kNoDevice: return "no_device";
        case TransferStatus::kError: return "error";
    }
    return "unknown";
}

FirmwareLoadReport load_firmware(FalconTransport& t, std::span<const std::uint8_t> image,
                                 const FirmwareLoadOptions& o) {
    FirmwareLoadReport r;
    r.bytes = image.size();
    if (image.empty()) {
        r.error = "the firmware image is empty";
        return r;
    }
    const int attempts = std::clamp(o.attempts, 1, 100);
    for (r.attempts = 1; r.attempts <= attempts; ++r.attempts) {
        std::string error;
        bool mismatch = false;
        Step s = requests(t, firmware_mode_requests(), o.timeout_ms, error);
        if (s == Step::kOk) {
            s = handshake(t, o, error);
            if (s == Step::kFailed) ++r.handshake_failures;
        }
        if (s == Step::kOk) s = requests(t, firmware_baud_requests(), o.timeout_ms, error);
        if (s == Step::kOk) s = loader_check(t, o, error);
        if (s == Step::kOk) s = send_image(t, image, o, mismatch, error);
        if (mismatch) ++r.echo_mismatches;
        if (s == Step::kOk) s = requests(t, normal_mode_requests(), o.timeout_ms, error);
        r.error = error;
        if (s == Step::kOk) {
            r.ok = true;
            r.error.clear();
            return r;
        }
        if (s == Step::kGone) return r;
    }
    r.attempts = attempts;
    return r;
}

bool set_normal_mode(FalconTransport& t, int timeout_ms, std::string& error) {
    return requests(t, normal_mode_requests(), timeout_ms, error) == Step::kOk;
}

bool firmware_running(FalconTransport& t, int tries, int timeout_us) {
    const Frame zero = encode_command(FalconCommand{});
    std::array<std::uint8_t, kUsbPacketBytes> packet{};
    StateFramer framer;
    for (int i = 0; i < tries; ++i) {
        std::size_t got = 0;
        const TransferStatus s = t.exchange(zero, packet, timeout_us, got);
        if (s == TransferStatus::kNoDevice) return false;
        std::span<const std::uint8_t> data;
        if (s == TransferStatus::kOk && split_in_packet(std::span<const std::uint8_t>(packet.data(), got), data) &&
            framer.feed(data))
            return true;
    }
    return false;
}

std::string firmware_missing_message() {
    return "Novint Falcon: its firmware is not loaded and no firmware file was given: pass --falcon-firmware FILE "
           "(or \"device\": {\"firmware\": \"FILE\"} in a scene) naming the Falcon firmware from your own Novint "
           "driver installation (e.g. novint.bin from its TestUtilities folder); tridex does not ship it";
}

std::vector<std::uint8_t> read_firmware_file(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw Error("--falcon-firmware: '" + path +
                    "' is not a file (give the Falcon firmware from your own installation)");
    const auto size = std::filesystem::file_size(path, ec);
    if (ec || size == 0 || size > 65536)
        throw Error("--falcon-firmware: '" + path + "' is " +
                    (ec          ? "unreadable"
                     : size == 0 ? "empty"
                                 : "larger than 64 KiB") +
                    ": not a Falcon firmware image");
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size));
    std::ifstream in(path, std::ios::binary);
    if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())))
        throw Error("--falcon-firmware: cannot read '" + path + "'");
    return bytes;
}

std::vector<std::uint8_t> emulator_firmware_image() {
    std::vector<std::uint8_t> out(1024);
    std::uint32_t x = 0x9e3779b9u;  // xorshift32: a fixed pattern with every byte value, including '<' and '>'
    for (std::uint8_t& b : out) {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        b = static_cast<std::uint8_t>(x >> 24);
    }
    return out;
}

}  // namespace tridex::devices::falcon
