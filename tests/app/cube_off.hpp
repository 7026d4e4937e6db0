// tests/app/cube_off.hpp - a closed cube mesh file for tests that place reference objects.
#pragma once

#include <filesystem>
#include <fstream>

namespace tridex::app::test {

/// Writes an OFF cube of side 2 centred on the origin (8 vertices, 12 outward triangles) to `path`.
inline void write_cube_off(const std::filesystem::path& path) {
    std::ofstream(path) << "OFF\n8 12 0\n-1 -1 -1\n1 -1 -1\n1 1 -1\n-1 1 -1\n-1 -1 1\n1 -1 1\n1 1 1\n-1 1 1\n"
                           "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 2 3 7\n3 2 7 6\n3 1 2 6\n3 1 6 5\n"
                           "3 0 4 7\n3 0 7 3\n";
}

}  // namespace tridex::app::test
