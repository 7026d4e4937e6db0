// tests/fuzz/fuzz_mesh_seeds.hpp - a closed tetrahedron in every mesh format the readers take (OFF and PLY, ASCII
// and binary; OBJ; STL, ASCII and binary): seeds small enough for the fuzzer to mutate quickly.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace tridex::fuzz {

/// One seed: the fuzz target it belongs to, a file name and its bytes.
struct MeshSeed {
    std::string target, name, bytes;
};

namespace detail {

inline constexpr std::array<std::array<float, 3>, 4> kTetraVertices{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
inline constexpr std::array<std::array<std::uint32_t, 3>, 4> kTetraFaces{{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};

/// Appends the 4 bytes of `v` (a float or a 32-bit integer), big-endian when `big`.
template <class T>
void put4(std::string& out, T v, bool big) {
    std::uint32_t u = 0;
    std::memcpy(&u, &v, 4);
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>(u >> (big ? 24 - 8 * i : 8 * i)));
}

/// The tetrahedron as an ASCII file: a header, then `vertex` and `face` per element (ASCII numbers).
inline std::string ascii(const std::string& header, const std::string& v, const std::string& f) {
    std::string out = header;
    for (const auto& p : kTetraVertices)
        out += v + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
    for (const auto& t : kTetraFaces)
        out += f + std::to_string(t[0] + (f == "f " ? 1 : 0)) + " " + std::to_string(t[1] + (f == "f " ? 1 : 0)) + " " +
               std::to_string(t[2] + (f == "f " ? 1 : 0)) + "\n";
    return out;
}

/// Binary OFF (big-endian) or PLY (little- or big-endian, uchar face counts) bodies.
inline std::string binary_body(bool big, bool ply) {
    std::string out;
    for (const auto& p : kTetraVertices)
        for (const float c : p) put4(out, c, big);
    for (const auto& t : kTetraFaces) {
        if (ply) out.push_back(3);
        else put4(out, std::uint32_t{3}, true);
        for (const std::uint32_t i : t) put4(out, i, big);
        if (!ply) put4(out, std::uint32_t{0}, true);
    }
    return out;
}

/// Binary STL: 80-byte header, count, then per triangle a normal, three corners and a 2-byte attribute.
inline std::string binary_stl() {
    std::string out(80, ' ');
    put4(out, std::uint32_t{4}, false);
    for (const auto& t : kTetraFaces) {
        for (int k = 0; k < 3; ++k) put4(out, 0.0f, false);
        for (const std::uint32_t i : t)
            for (const float c : kTetraVertices[i]) put4(out, c, false);
        out += std::string(2, '\0');
    }
    return out;
}

/// ASCII STL.
inline std::string ascii_stl() {
    std::string out = "solid tetra\n";
    for (const auto& t : kTetraFaces) {
        out += "facet normal 0 0 0\nouter loop\n";
        for (const std::uint32_t i : t)
            out += "vertex " + std::to_string(kTetraVertices[i][0]) + " " + std::to_string(kTetraVertices[i][1]) + " " +
                   std::to_string(kTetraVertices[i][2]) + "\n";
        out += "endloop\nendfacet\n";
    }
    return out + "endsolid tetra\n";
}

}  // namespace detail

/// Every mesh seed.
inline std::vector<MeshSeed> mesh_seeds() {
    using namespace detail;
    const std::string ply_head = "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                                 "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
    return {
        {"off", "tetra.off", ascii("OFF\n# a tetrahedron\n4 4 6\n", "", "3 ")},
        {"off", "tetra_binary.off", "OFF BINARY\n" + std::string("\0\0\0\4\0\0\0\4\0\0\0\6", 12) + binary_body(true, false)},
        {"ply", "tetra_ascii.ply", ascii("ply\nformat ascii 1.0\ncomment seed\n" + ply_head, "", "3 ")},
        {"ply", "tetra_le.ply", "ply\nformat binary_little_endian 1.0\n" + ply_head + binary_body(false, true)},
        {"ply", "tetra_be.ply", "ply\nformat binary_big_endian 1.0\n" + ply_head + binary_body(true, true)},
        {"obj", "tetra.obj", ascii("# a tetrahedron\n", "v ", "f ")},
        {"stl", "tetra_ascii.stl", ascii_stl()},
        {"stl", "tetra_binary.stl", binary_stl()},
    };
}

}  // namespace tridex::fuzz
