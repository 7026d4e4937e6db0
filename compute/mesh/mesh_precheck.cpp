// compute/mesh/mesh_precheck.cpp - the file itself, and header and index sanity checks of STL and OBJ files.
#include "compute/mesh/mesh_precheck.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "core/text/printable.hpp"

namespace tridex::compute {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& reason) { throw Error(path + ": " + reason); }

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

void check_stl(const std::string& path, std::ifstream& in, std::uint64_t size) {
    char head[84] = {};
    in.read(head, sizeof head);
    const auto got = static_cast<std::uint64_t>(in.gcount());
    std::size_t i = 0;
    while (i < got && std::isspace(static_cast<unsigned char>(head[i]))) ++i;
    const bool says_solid = got - i >= 5 && std::memcmp(head + i, "solid", 5) == 0;
    if (got == 84) {
        const auto* b = reinterpret_cast<const unsigned char*>(head + 80);
        const std::uint64_t n = b[0] | (b[1] << 8) | (b[2] << 16) | (static_cast<std::uint64_t>(b[3]) << 24);
        if (84 + 50 * n == size) {
            if (n == 0) fail(path, "no triangles (binary STL with 0 facets)");
            // OpenMesh merges STL vertices through an ordered map, where a NaN compares equal to
            // anything; catch non-finite coordinates here, where the facet can still be named.
            char facet[50];
            for (std::uint64_t f = 0; f < n && in.read(facet, sizeof facet); ++f) {
                for (int k = 0; k < 9; ++k) {
                    float x;
                    std::memcpy(&x, facet + 12 + 4 * k, sizeof x);
                    if (!std::isfinite(x))
                        fail(path, "facet " + std::to_string(f) + " has a non-finite vertex coordinate");
                }
            }
            return;
        }
        if (!says_solid)
            fail(path, "binary STL header declares " + std::to_string(n) + " facets (" + std::to_string(84 + 50 * n) +
                           " bytes) but the file has " + std::to_string(size) + " bytes");
    }
    if (!says_solid) fail(path, "not an STL file (too short for binary, no 'solid' keyword for ASCII)");
}

// What separates words in an OBJ line: every character isspace() takes (OpenMesh reads words with >>, so "f\r1 2 3"
// and "\ff 1 2 3" are face lines to it).
constexpr const char* kObjSpace = " \t\r\v\f";

void check_obj(const std::string& path, std::ifstream& in) {
    std::string line;
    std::int64_t vertices = 0;
    std::size_t line_no = 0;
    while (std::getline(in, line)) {
        ++line_no;
        std::size_t p = line.find_first_not_of(kObjSpace);
        if (p == std::string::npos) continue;
        auto is_key = [&](const char* key) {
            const std::size_t n = std::strlen(key);
            return line.compare(p, n, key) == 0 &&
                   (p + n == line.size() || std::strchr(kObjSpace, line[p + n]) != nullptr);
        };
        if (is_key("v")) {
            ++vertices;
        } else if (is_key("f")) {
            const std::string where = path + ":" + std::to_string(line_no) + ": ";
            std::size_t refs = 0, q = p + 1;
            while (true) {
                q = line.find_first_not_of(kObjSpace, q);
                if (q == std::string::npos || line[q] == '#') break;
                const std::size_t end = std::min(line.find_first_of(kObjSpace, q), line.size());
                const std::string_view tok(line.data() + q, end - q);
                const std::string_view idx = tok.substr(0, tok.find('/'));
                std::int64_t v = 0;
                const auto r = std::from_chars(idx.data(), idx.data() + idx.size(), v);
                if (idx.empty() || r.ec != std::errc() || r.ptr != idx.data() + idx.size())
                    throw Error(where + "malformed face vertex reference '" + printable(tok) + "'");
                if (v == 0) throw Error(where + "face vertex index 0 is invalid (OBJ indices start at 1)");
                const std::int64_t resolved = v > 0 ? v : vertices + v + 1;
                if (resolved < 1 || resolved > vertices)
                    throw Error(where + "face vertex index " + std::to_string(v) + " out of range (" +
                                std::to_string(vertices) + " vertices defined so far)");
                ++refs;
                q = end;
            }
            if (refs < 3)
                throw Error(where + "face with " + std::to_string(refs) + " vertex references (needs at least 3)");
        }
    }
}

}  // namespace

MeshFormat mesh_format_of(const std::string& path) {
    const std::string ext = lower(std::filesystem::path(path).extension().string());
    if (ext == ".off") return MeshFormat::kOff;
    if (ext == ".obj") return MeshFormat::kObj;
    if (ext == ".ply") return MeshFormat::kPly;
    if (ext == ".stl") return MeshFormat::kStl;
    fail(path, "unknown mesh file extension '" + ext + "' (expected .off, .obj, .ply or .stl)");
}

void precheck_mesh_file(const std::string& path, MeshFormat format) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) fail(path, "no such file");
    if (!std::filesystem::is_regular_file(status)) fail(path, "not a regular file");
    const std::uint64_t size = std::filesystem::file_size(path, ec);
    if (ec) fail(path, "cannot read file size: " + ec.message());
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "cannot open file for reading");
    if (size == 0) fail(path, "file is empty");
    switch (format) {
        case MeshFormat::kOff:
        case MeshFormat::kPly: break;  // their readers check every count and number as they go
        case MeshFormat::kStl: check_stl(path, in, size); break;
        case MeshFormat::kObj: check_obj(path, in); break;
    }
}

}  // namespace tridex::compute
