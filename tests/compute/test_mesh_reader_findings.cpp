// Tests of the mesh readers' faults found by fuzzing (tests/fuzz/fuzz_obj.cpp, fuzz_stl.cpp), each with its input
// as bytes.
#include <gtest/gtest.h>

#include <malloc.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "compute/mesh/mesh_io.hpp"
#include "core/error.hpp"

namespace tridex::compute {
namespace {

/// Writes `bytes` to a file named `name` in the temporary folder; returns its path.
std::string temp_file(const std::string& name, const std::string& bytes) {
    const std::string path =
        (std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_" + name)).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
}

/// Bytes the allocator holds for the program now (mallinfo2; 0 where a sanitizer replaces malloc, which then
/// finds leaks itself).
std::size_t allocated_bytes() { return mallinfo2().uordblks; }

TEST(MeshReaderFindings, ReadingMeshesThroughOpenMeshKeepsNoMemory) {
    // The fuzzer's leak report, for any OBJ or STL: each read connected OpenMesh's log streams to a capture buffer
    // and back, and OpenMesh's disconnect never frees a stream target (48 bytes lost per file). A closed tetrahedron
    // and a file OpenMesh refuses are each read many times; the memory held afterwards must not grow with the count.
    const std::string good = temp_file("tetra.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    const std::string bad = temp_file("bad.stl", std::string(80, 'x') + std::string("\x01\0\0\0", 4) + std::string(50, '\0'));
    auto read_both = [&] {
        EXPECT_EQ(load_closed_mesh(good).triangles.size(), 4u);
        EXPECT_THROW(load_closed_mesh(bad), Error);
    };
    read_both();  // the first read detaches OpenMesh's streams from the terminal, once
    const std::size_t before = allocated_bytes();
    for (int i = 0; i < 2000; ++i) read_both();
    const std::size_t after = allocated_bytes();
    EXPECT_LT(after > before ? after - before : 0, std::size_t{16} << 10) << "kept " << (after - before) << " bytes";
    std::filesystem::remove(good);
    std::filesystem::remove(bad);
}

}  // namespace
}  // namespace tridex::compute
