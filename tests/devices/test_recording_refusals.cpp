// Tests of devices/recording's refusals found by fuzzing (tests/fuzz/fuzz_recording.cpp): each holds the input
// that was refused badly, as bytes, and checks the refusal is one printable line naming the file and the byte.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "devices/recording.hpp"

namespace tridex::devices {
namespace {

/// A 32-byte version 2 preamble with no ticks and a header text of `text`, then the text (checksum not set: the
/// header text is read before the checksum is checked).
std::string recording_with_header_text(const std::string& text) {
    std::string b("TRDXREC\0", 8);
    auto u32 = [&b](std::uint32_t v) {
        for (int i = 0; i < 4; ++i) b.push_back(static_cast<char>(v >> (8 * i)));
    };
    u32(2), u32(397), u32(0), u32(0), u32(0), u32(static_cast<std::uint32_t>(text.size()));
    return b + text;
}

/// The refusal of read_recording for a file holding `bytes`.
std::string refusal_of(const std::string& name, const std::string& bytes, std::string& path) {
    path = (std::filesystem::temp_directory_path() / (name + "." + std::to_string(::getpid()))).string();
    std::ofstream(path, std::ios::binary) << bytes;
    std::string message;
    try {
        read_recording(path);
    } catch (const Error& e) {
        message = e.what();
    }
    std::filesystem::remove(path);
    return message;
}

TEST(RecordingRefusals, HeaderTextThatIsNotJsonIsQuotedPrintably) {
    // The fuzzer's input, reduced: a header text whose bytes after a key are a control character and a byte that
    // is not ASCII. The JSON parser's reason quotes them; the refusal used to print them raw.
    std::string path;
    const std::string message =
        refusal_of("fuzz_header", recording_with_header_text("{\"period_s\"\x01\xff\x1b[2J}"), path);
    ASSERT_FALSE(message.empty()) << "the recording was not refused";
    EXPECT_EQ(message.rfind(path + ": header text (byte 32) is not JSON: ", 0), 0u) << message;
    for (const char c : message)
        EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "byte " << int(static_cast<unsigned char>(c)) << " in: " << message;
    EXPECT_EQ(message.find("[json.exception"), std::string::npos) << message;
}

}  // namespace
}  // namespace tridex::devices
