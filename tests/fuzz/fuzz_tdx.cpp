// tests/fuzz/fuzz_tdx.cpp - libFuzzer target: load_tdx on a .tdx model file (sizes, checksums, zstd frames,
// every interval), with a 64 MiB model budget.
#include <cstdint>

#include "compute/model/tdx_file.hpp"
#include "tests/fuzz/fuzz_support.hpp"

/// One fuzz input as the bytes of a .tdx file.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = tridex::fuzz::input_file("fuzz.tdx", data, size);
    tridex::fuzz::expect_clean(path, [&] { tridex::compute::load_tdx(path, std::size_t{64} << 20); });
    return 0;
}
