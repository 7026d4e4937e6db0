// tests/fuzz/fuzz_ply.cpp - libFuzzer target: the strict PLY reader (read_ply, in memory), then what
// load_closed_mesh does with its soup (finite positions, weld, closed and oriented).
#include <cstdint>

#include "compute/mesh/mesh_io.hpp"
#include "compute/mesh/ply_reader.hpp"
#include "tests/fuzz/fuzz_support.hpp"

/// One fuzz input as the bytes of an PLY file.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = "fuzz.ply";
    tridex::fuzz::expect_clean(path, [&] {
        tridex::compute::closed_mesh_from_soup(tridex::compute::read_ply(path, tridex::fuzz::as_text(data, size)), path);
    });
    return 0;
}
