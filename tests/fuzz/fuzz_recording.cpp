// tests/fuzz/fuzz_recording.cpp - libFuzzer target: read_recording on a TRDXREC haptic recording.
#include <cstdint>

#include "devices/recording.hpp"
#include "tests/fuzz/fuzz_support.hpp"

/// One fuzz input as the bytes of a recording file.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = tridex::fuzz::input_file("fuzz.trdxrec", data, size);
    tridex::fuzz::expect_clean(path, [&] { tridex::devices::read_recording(path); });
    return 0;
}
