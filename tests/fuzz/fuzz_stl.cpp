// tests/fuzz/fuzz_stl.cpp - libFuzzer target: load_closed_mesh on an STL file (precheck_mesh_file, then
// OpenMesh's reader, weld, closed and oriented).
#include <cstdint>

#include "compute/mesh/mesh_io.hpp"
#include "tests/fuzz/fuzz_support.hpp"

/// One fuzz input as the bytes of an STL file.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = tridex::fuzz::input_file("fuzz.stl", data, size);
    tridex::fuzz::expect_clean(path, [&] { tridex::compute::load_closed_mesh(path); });
    return 0;
}
