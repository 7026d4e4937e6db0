// compute/mesh/mesh_precheck.cpp - header and index sanity checks of OFF, PLY, STL and OBJ files.
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
#include <sstream>
#include <string_view>
#include <vector>

#include "core/error.hpp"

namespace tridex::compute {
namespace {

using u128 = unsigned __int128;

[[noreturn]] void fail(const std::string& path, const std::string& reason) { throw Error(path + ": " + reason); }

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

/// Parses a whole token as an unsigned 64-bit integer; false when it is not one.
bool parse_u64(std::string_view tok, std::uint64_t& out) {
    if (tok.empty()) return false;
    const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), out);
    return r.ec == std::errc() && r.ptr == tok.data() + tok.size();
}

/// Whitespace-separated tokens of a stream, skipping '#' comments to the end of their line.
class Tokens {
public:
    explicit Tokens(std::istream& in) : in_(in) {}
    /// Next token, or empty at end of stream.
    std::string next() {
        std::string tok;
        int c;
        while ((c = in_.get()) != EOF) {
            if (c == '#') {
                while ((c = in_.get()) != EOF && c != '\n') {}
                continue;
            }
            if (!std::isspace(c)) break;
        }
        if (c == EOF) return tok;
        tok.push_back(static_cast<char>(c));
        while ((c = in_.peek()) != EOF && !std::isspace(c) && c != '#') tok.push_back(static_cast<char>(in_.get()));
        return tok;
    }
    /// Bytes consumed so far.
    std::uint64_t position() {
        const auto p = in_.tellg();
        return p < 0 ? 0 : static_cast<std::uint64_t>(p);
    }

private:
    std::istream& in_;
};

/// Reads the vertex block of an ASCII OFF body (stream positioned after the counts): every vertex
/// line (Geomview layout, one vertex per line) must start with three finite numbers. Stream parsers silently stop at "nan" or "1e999"; this
/// names the line instead.
void check_off_ascii_vertices(const std::string& path, std::ifstream& in, std::uint64_t nv) {
    // Line numbers: count the newlines before the current position.
    const auto here = in.tellg();
    in.seekg(0);
    std::size_t line_no = 1;
    for (std::streamoff i = 0; i < here; ++i)
        if (in.get() == '\n') ++line_no;
    std::string line;
    std::getline(in, line);  // rest of the counts line
    std::uint64_t seen = 0;
    while (seen < nv && std::getline(in, line)) {
        ++line_no;
        const std::size_t hash = line.find('#');
        if (hash != std::string::npos) line.resize(hash);
        std::istringstream ls(line);
        std::string tok;
        int coords = 0;
        while (coords < 3 && ls >> tok) {
            char* end = nullptr;
            const double v = std::strtod(tok.c_str(), &end);
            if (end != tok.c_str() + tok.size() || !std::isfinite(v))
                fail(path + ":" + std::to_string(line_no),
                     "vertex " + std::to_string(seen) + " coordinate '" + tok.substr(0, 32) + "' is not a finite number");
            ++coords;
        }
        if (coords == 0) continue;  // blank or comment line
        if (coords < 3) fail(path + ":" + std::to_string(line_no), "vertex " + std::to_string(seen) + " has fewer than 3 coordinates");
        ++seen;
    }
    // Fewer vertex lines than declared (vertices packed several to a line): OpenMesh parses the rest.
}

void check_off(const std::string& path, std::ifstream& in, std::uint64_t size) {
    Tokens tokens(in);
    const std::string key = tokens.next();
    if (key.size() < 3 || key.compare(key.size() - 3, 3, "OFF") != 0)
        fail(path, "not an OFF file (first keyword is '" + key.substr(0, 32) + "', expected OFF)");
    std::uint64_t dim = key.rfind("4OFF") != std::string::npos ? 4 : 3;
    std::string tok = tokens.next();
    if (key.find('n') != std::string::npos) {  // nOFF: the vertex dimension comes first
        if (!parse_u64(tok, dim) || dim < 3) fail(path, "OFF header: bad vertex dimension '" + tok.substr(0, 32) + "'");
        tok = tokens.next();
    }
    bool binary = false;
    if (tok == "BINARY") {
        binary = true;
        tok = tokens.next();
    }
    std::uint64_t nv = 0, nf = 0, ne = 0;
    if (!parse_u64(tok, nv)) fail(path, "OFF header: vertex count '" + tok.substr(0, 32) + "' is not a non-negative integer");
    tok = tokens.next();
    if (!parse_u64(tok, nf)) fail(path, "OFF header: face count '" + tok.substr(0, 32) + "' is not a non-negative integer");
    tok = tokens.next();
    if (!parse_u64(tok, ne)) fail(path, "OFF header: edge count '" + tok.substr(0, 32) + "' is not a non-negative integer");
    // Lower bound of the body size: every vertex has `dim` numbers, every face at least 4 (count + 3 indices).
    const u128 numbers = static_cast<u128>(nv) * dim + static_cast<u128>(nf) * 4;
    const u128 need = binary ? numbers * 4 : numbers * 2 - 1;
    const std::uint64_t body = size - std::min(size, tokens.position());
    if (need > body)
        fail(path, "OFF header claims " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                       " faces, impossible in a file of " + std::to_string(size) + " bytes");
    if (nv < 4) fail(path, "OFF header declares " + std::to_string(nv) + " vertices; a closed mesh needs at least 4");
    if (nf == 0) fail(path, "no triangles (OFF header declares 0 faces)");
    if (nv > 0xffffffffull || nf > 0xffffffffull)
        fail(path, "OFF header counts " + std::to_string(nv) + " vertices, " + std::to_string(nf) +
                       " faces exceed 32-bit indices");
    if (!binary) check_off_ascii_vertices(path, in, nv);
}

int ply_scalar_size(const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

void check_ply(const std::string& path, std::ifstream& in, std::uint64_t size) {
    std::string line;
    if (!std::getline(in, line) || line.substr(0, 3) != "ply") fail(path, "not a PLY file (missing 'ply' magic line)");
    bool binary = false, have_format = false, have_end = false;
    u128 need = 0;               // minimum body bytes of the elements declared so far
    u128 element_count = 0;      // count of the element being declared
    u128 element_bytes = 0;      // minimum bytes of one such element
    auto close_element = [&] { need += element_count * element_bytes; };
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (static_cast<std::uint64_t>(in.tellg()) > (1u << 20)) break;
        std::istringstream ls(line);
        std::string word;
        ls >> word;
        if (word == "end_header") {
            have_end = true;
            break;
        }
        if (word == "format") {
            std::string kind;
            ls >> kind;
            if (kind == "ascii") binary = false;
            else if (kind == "binary_little_endian" || kind == "binary_big_endian") binary = true;
            else fail(path, "PLY header: unknown format '" + kind.substr(0, 32) + "'");
            have_format = true;
        } else if (word == "element") {
            close_element();
            std::string name, count;
            ls >> name >> count;
            std::uint64_t n = 0;
            if (!parse_u64(count, n)) fail(path, "PLY header: element '" + name + "' count '" + count.substr(0, 32) + "' is not a non-negative integer");
            element_count = n;
            element_bytes = 0;
        } else if (word == "property") {
            std::string type;
            ls >> type;
            if (type == "list") {
                std::string count_type, item_type;
                ls >> count_type >> item_type;
                const int cs = ply_scalar_size(count_type);
                if (cs == 0 || ply_scalar_size(item_type) == 0) fail(path, "PLY header: bad list property types '" + count_type + " " + item_type + "'");
                element_bytes += binary ? cs : 2;
            } else {
                const int s = ply_scalar_size(type);
                if (s == 0) fail(path, "PLY header: unknown property type '" + type.substr(0, 32) + "'");
                element_bytes += binary ? s : 2;
            }
        }  // other lines (comment, obj_info, free text some exporters write) carry no sizes
    }
    if (!have_end) fail(path, "PLY header has no end_header line");
    if (!have_format) fail(path, "PLY header has no format line");
    close_element();
    const std::uint64_t body = size - std::min<std::uint64_t>(size, static_cast<std::uint64_t>(in.tellg()));
    if (!binary && need > 0) need -= 1;  // the last ASCII number needs no separator
    if (need > body)
        fail(path, "PLY header declares more elements than a file of " + std::to_string(size) + " bytes can hold");
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

void check_obj(const std::string& path, std::ifstream& in) {
    std::string line;
    std::int64_t vertices = 0;
    std::size_t line_no = 0;
    while (std::getline(in, line)) {
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::size_t p = line.find_first_not_of(" \t");
        if (p == std::string::npos) continue;
        auto is_key = [&](const char* key) {
            const std::size_t n = std::strlen(key);
            return line.compare(p, n, key) == 0 && (p + n == line.size() || line[p + n] == ' ' || line[p + n] == '\t');
        };
        if (is_key("v")) {
            ++vertices;
        } else if (is_key("f")) {
            const std::string where = path + ":" + std::to_string(line_no) + ": ";
            std::size_t refs = 0, q = p + 1;
            while (true) {
                q = line.find_first_not_of(" \t", q);
                if (q == std::string::npos || line[q] == '#') break;
                const std::size_t end = std::min(line.find_first_of(" \t", q), line.size());
                const std::string_view tok(line.data() + q, end - q);
                const std::string_view idx = tok.substr(0, tok.find('/'));
                std::int64_t v = 0;
                const auto r = std::from_chars(idx.data(), idx.data() + idx.size(), v);
                if (idx.empty() || r.ec != std::errc() || r.ptr != idx.data() + idx.size())
                    throw Error(where + "malformed face vertex reference '" + std::string(tok.substr(0, 32)) + "'");
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
        case MeshFormat::kOff: check_off(path, in, size); break;
        case MeshFormat::kPly: check_ply(path, in, size); break;
        case MeshFormat::kStl: check_stl(path, in, size); break;
        case MeshFormat::kObj: check_obj(path, in); break;
    }
}

}  // namespace tridex::compute
