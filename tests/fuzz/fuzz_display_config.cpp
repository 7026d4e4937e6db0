// tests/fuzz/fuzz_display_config.cpp - libFuzzer target: load_display_config on a display config file (JSON).
#include <cstdint>

#include "renderer/camera/display_config.hpp"
#include "tests/fuzz/fuzz_support.hpp"

/// One fuzz input as the bytes of a display config file.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = tridex::fuzz::input_file("fuzz_display.json", data, size);
    tridex::fuzz::expect_clean(path, [&] { tridex::renderer::load_display_config(path); });
    return 0;
}
