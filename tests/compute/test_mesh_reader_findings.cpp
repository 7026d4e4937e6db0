// Tests of the mesh readers' faults found by fuzzing (tests/fuzz/fuzz_obj.cpp, fuzz_stl.cpp, fuzz_ply.cpp), each
// with its input as bytes.
#include <gtest/gtest.h>

#include <malloc.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "compute/mesh/mesh_io.hpp"
#include "compute/mesh/ply_reader.hpp"
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

/// The refusal of `read` (a tridex::Error's message); empty when it returned.
template <class Read>
std::string refusal_of(Read&& read) {
    try {
        read();
    } catch (const Error& e) {
        return e.what();
    }
    return {};
}

/// True when every byte of `s` is printable ASCII.
bool printable_line(const std::string& s) {
    for (const char c : s)
        if (c < 0x20 || c == 0x7f) return false;
    return true;
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

TEST(MeshReaderFindings, ObjFaceLineAfterAnyWhitespaceIsChecked) {
    // The fuzzer's input, reduced: "f" then a carriage return and a reference without an index. The precheck split
    // words at spaces and tabs only, so it took the line for no face; OpenMesh splits at every white space, took it
    // for a face with no vertices and failed an assertion (abort). Now the precheck refuses it, naming the line.
    const std::string path = temp_file("cr_face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf\r/0 2 3\n");
    const std::string message = refusal_of([&] { load_closed_mesh(path); });
    EXPECT_EQ(message, path + ":4: malformed face vertex reference '/0'");
    // The fuzzer's whole input (form feeds, carriage returns, bytes that are not ASCII).
    static const char kFuzzed[] = "\x0c\x1a" "f 3 2\nf\r/0 2 4\n\x0c\x1a" "f 6 2\nf\r 0 2 4\nf!\nv1 3 2\nf\r 0 2 4\nf!\n"
                                  "v 1*0\x0c\xff\xff\xff\xac";
    const std::string fuzzed(kFuzzed, sizeof kFuzzed - 1);
    const std::string whole = temp_file("fuzzed.obj", fuzzed);
    const std::string refused = refusal_of([&] { load_closed_mesh(whole); });
    EXPECT_EQ(refused.rfind(whole + ":2: ", 0), 0u) << refused;
    for (const std::string& p : {path, whole}) std::filesystem::remove(p);
}

TEST(MeshReaderFindings, PlyElementNameIsQuotedPrintably) {
    // The fuzzer's input, reduced: an element whose name holds a byte that is not ASCII and an escape, with a value
    // that is not a number; the refusal quoted the element's name raw.
    const std::string ply = "ply\nformat ascii 1.0\nelement v\xff\x1b 1\nproperty float y\nelement vertex 0\n"
                            "property float x\nproperty float y\nproperty float z\nelement face 0\n"
                            "property list uchar int vertex_indices\nend_header\nty\n";
    const std::string message = refusal_of([&] { read_ply("fuzz.ply", ply); });
    EXPECT_EQ(message, "fuzz.ply:12: v\\xff\\x1b 0 property 'y' 'ty' is not a number");
    EXPECT_TRUE(printable_line(message)) << message;
}

}  // namespace
}  // namespace tridex::compute
