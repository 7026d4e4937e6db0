// compute/mesh/off_reader.cpp - OFF (ASCII and binary) into a polygon soup, every count checked before use.
#include "compute/mesh/off_reader.hpp"

#include <bit>
#include <cmath>
#include <cstdint>

#include "compute/mesh/mesh_text.hpp"
#include "core/error.hpp"
#include "core/text/printable.hpp"

namespace tridex::compute {
namespace {

using u128 = unsigned __int128;

[[noreturn]] void fail(const std::string& where, const std::string& reason) { throw Error(where + ": " + reason); }

std::string quoted(std::string_view token) { return "'" + printable(token) + "'"; }

/// The header: what each vertex carries, the counts and where the body starts.
struct OffHeader {
    int coords = 3;             ///< coordinates per vertex, the homogeneous one included
    bool homogeneous = false;   ///< 4OFF: the last coordinate divides the others
    int extras = 0;             ///< numbers per vertex after the coordinates (normal, colour, texture)
    bool binary = false;
    std::int64_t vertices = 0, faces = 0;
    std::size_t body = 0;       ///< byte offset of the first vertex
};

/// Parses the keyword prefix ("ST", "C", "N", "4", "n", in that order) of `keyword` (which ends in "OFF").
bool parse_prefix(std::string_view prefix, OffHeader& h, bool& dimension_follows) {
    auto take = [&](std::string_view p) {
        if (prefix.substr(0, p.size()) != p) return false;
        prefix.remove_prefix(p.size());
        return true;
    };
    if (take("ST")) h.extras += 2;
    if (take("C")) h.extras += 4;
    if (take("N")) h.extras += 3;
    if (take("4")) h.homogeneous = true;
    dimension_follows = take("n");
    return prefix.empty();
}

std::int64_t header_count(std::string_view token, const std::string& path, const char* what) {
    std::int64_t n = 0;
    if (!parse_whole_i64(token, n) || n < 0)
        fail(path, std::string("OFF header: ") + what + " count " + quoted(token) + " is not a non-negative integer");
    return n;
}

OffHeader parse_header(const std::string& path, std::string_view bytes) {
    OffHeader h;
    TextScanner s(bytes, 0, true);
    std::string_view tok = s.next();
    std::int64_t probe = 0;
    if (!parse_whole_i64(tok, probe)) {  // the keyword is optional: a file may start with the counts
        if (tok.size() < 3 || tok.substr(tok.size() - 3) != "OFF")
            fail(path, "not an OFF file (first keyword is " + quoted(tok) + ", expected OFF)");
        bool dimension_follows = false;
        if (!parse_prefix(tok.substr(0, tok.size() - 3), h, dimension_follows))
            fail(path, "OFF header: unknown keyword " + quoted(tok) + " (expected [ST][C][N][4][n]OFF)");
        tok = s.next();
        if (dimension_follows) {
            std::int64_t dim = 0;
            if (!parse_whole_i64(tok, dim) || dim < 3 || dim > 64)
                fail(path, "OFF header: bad vertex dimension " + quoted(tok) + " (3 to 64)");
            h.coords = static_cast<int>(dim);
            tok = s.next();
        }
        if (tok == "BINARY") {
            if (dimension_follows) fail(path, "OFF header: nOFF BINARY is not supported (write the file as ASCII)");
            h.binary = true;
            s.skip_line();  // binary data starts after the first newline after BINARY
        }
    }
    if (h.homogeneous) ++h.coords;
    const int per_vertex = h.coords + h.extras;
    std::size_t counts_end = 0;
    if (h.binary) {
        const std::size_t at = s.offset();
        if (bytes.size() - at < 12) fail(path, "OFF BINARY header: the file ends before the three counts");
        const auto* p = reinterpret_cast<const unsigned char*>(bytes.data()) + at;
        h.vertices = static_cast<std::int32_t>(load_uint(p, 4, true));
        h.faces = static_cast<std::int32_t>(load_uint(p + 4, 4, true));
        if (h.vertices < 0 || h.faces < 0)
            fail(path, "OFF BINARY header: negative count (" + std::to_string(h.vertices) + " vertices, " +
                           std::to_string(h.faces) + " faces)");
        counts_end = at + 12;
    } else {
        if (tok.empty()) fail(path, "OFF header: the file ends before the counts");
        h.vertices = header_count(tok, path, "vertex");
        h.faces = header_count(s.next(), path, "face");
        header_count(s.next(), path, "edge");
        counts_end = s.offset();
    }
    // The least the body can hold: every vertex its numbers, every face a count and three indices (binary: and a
    // colour count).
    const auto nv = static_cast<std::uint64_t>(h.vertices), nf = static_cast<std::uint64_t>(h.faces);
    const u128 numbers = static_cast<u128>(nv) * per_vertex + static_cast<u128>(nf) * (h.binary ? 5 : 4);
    const u128 need = h.binary ? numbers * 4 : numbers * 2 - 1;
    if (need > bytes.size() - counts_end)
        fail(path, "OFF header claims " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                       " faces, impossible in a file of " + std::to_string(bytes.size()) + " bytes");
    if (nv < 4) fail(path, "OFF header declares " + std::to_string(nv) + " vertices; a closed mesh needs at least 4");
    if (nf == 0) fail(path, "no triangles (OFF header declares 0 faces)");
    if (nv > 0xffffffffull || nf > 0xffffffffull)
        fail(path, "OFF header counts " + std::to_string(nv) + " vertices, " + std::to_string(nf) +
                       " faces exceed 32-bit indices");
    h.body = counts_end;
    return h;
}

/// Adds the fan triangles of one face (indices already checked).
void add_fan(TriMesh& soup, const std::uint32_t* ids, std::size_t k) {
    for (std::size_t j = 1; j + 1 < k; ++j) soup.triangles.push_back({ids[0], ids[j], ids[j + 1]});
}

/// A vertex position from its coordinates, the homogeneous one divided out; false when that one is 0.
bool position(const double* c, const OffHeader& h, Vec3& out) {
    double w = 1.0;
    if (h.homogeneous) w = c[h.coords - 1];
    if (w == 0.0 || !std::isfinite(w)) return false;
    out = Vec3(c[0] / w, c[1] / w, c[2] / w);
    return true;
}

/// Adds vertex `v` from its coordinates; `where()` names the place in a refusal (a homogeneous coordinate of 0).
template <class Where>
void add_vertex(TriMesh& soup, const double* c, const OffHeader& h, std::int64_t v, const Where& where) {
    Vec3 p;
    if (!position(c, h, p)) fail(where(), "vertex " + std::to_string(v) + " has a homogeneous coordinate of 0");
    soup.positions.push_back(p);
}

void read_ascii(const std::string& path, std::string_view bytes, const OffHeader& h, TriMesh& soup) {
    TextScanner s(bytes, h.body, true);
    auto at = [&] { return path + ":" + std::to_string(s.line()); };
    double c[65];
    for (std::int64_t v = 0; v < h.vertices; ++v) {
        for (int k = 0; k < h.coords + h.extras; ++k) {
            const std::string_view tok = s.next();
            if (tok.empty()) fail(at(), "the file ends in vertex " + std::to_string(v) + " of " + std::to_string(h.vertices));
            double x = 0.0;
            const bool number = parse_whole_double(tok, x);
            if (k < h.coords && (!number || !std::isfinite(x)))
                fail(at(), "vertex " + std::to_string(v) + " coordinate " + quoted(tok) + " is not a finite number");
            if (!number) fail(at(), "vertex " + std::to_string(v) + " value " + quoted(tok) + " is not a number");
            if (k < h.coords) c[k] = x;
        }
        add_vertex(soup, c, h, v, at);
    }
    std::vector<std::uint32_t> ids;
    for (std::int64_t f = 0; f < h.faces; ++f) {
        const std::string_view tok = s.next();
        if (tok.empty()) fail(at(), "the file ends before face " + std::to_string(f) + " of " + std::to_string(h.faces));
        std::int64_t k = 0;
        if (!parse_whole_i64(tok, k) || k < 0)
            fail(at(), "face " + std::to_string(f) + " vertex count " + quoted(tok) + " is not a non-negative integer");
        if (k < 3) fail(at(), "face " + std::to_string(f) + " has " + std::to_string(k) + " vertices (needs at least 3)");
        if (static_cast<std::uint64_t>(k) * 2 - 1 > s.remaining())
            fail(at(), "face " + std::to_string(f) + " claims " + std::to_string(k) + " vertices, more than the " +
                           std::to_string(s.remaining()) + " bytes left can hold");
        ids.resize(static_cast<std::size_t>(k));
        for (std::int64_t j = 0; j < k; ++j) {
            const std::string_view id = s.next();
            std::int64_t i = 0;
            if (!parse_whole_i64(id, i) || i < 0 || i >= h.vertices)
                fail(at(), "face " + std::to_string(f) + " vertex index " + quoted(id) + " is not in 0.." +
                               std::to_string(h.vertices - 1));
            ids[static_cast<std::size_t>(j)] = static_cast<std::uint32_t>(i);
        }
        s.skip_line();  // the face's colour, if any
        add_fan(soup, ids.data(), ids.size());
    }
}

void read_binary(const std::string& path, std::string_view bytes, const OffHeader& h, TriMesh& soup) {
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    std::size_t pos = h.body;
    auto at = [&] { return path + ": byte " + std::to_string(pos); };
    auto word = [&](const char* what) {
        if (bytes.size() - pos < 4) fail(at(), std::string("the file ends in ") + what);
        const auto v = static_cast<std::uint32_t>(load_uint(data + pos, 4, true));
        pos += 4;
        return v;
    };
    double c[65];
    for (std::int64_t v = 0; v < h.vertices; ++v) {
        for (int k = 0; k < h.coords + h.extras; ++k) {
            const float x = std::bit_cast<float>(word("a vertex"));
            if (k < h.coords) c[k] = x;
        }
        add_vertex(soup, c, h, v, at);
    }
    std::vector<std::uint32_t> ids;
    for (std::int64_t f = 0; f < h.faces; ++f) {
        const auto k = static_cast<std::int32_t>(word("a face"));
        if (k < 3) fail(at(), "face " + std::to_string(f) + " has " + std::to_string(k) + " vertices (needs at least 3)");
        if (static_cast<std::uint64_t>(k) * 4 > bytes.size() - pos)
            fail(at(), "face " + std::to_string(f) + " claims " + std::to_string(k) + " vertices, more than the " +
                           std::to_string(bytes.size() - pos) + " bytes left can hold");
        ids.resize(static_cast<std::size_t>(k));
        for (auto& id : ids) {
            const auto i = static_cast<std::int32_t>(word("a face"));
            if (i < 0 || i >= h.vertices)
                fail(at(), "face " + std::to_string(f) + " vertex index " + std::to_string(i) + " is not in 0.." +
                               std::to_string(h.vertices - 1));
            id = static_cast<std::uint32_t>(i);
        }
        const auto colours = static_cast<std::int32_t>(word("a face"));
        if (colours < 0 || colours > 4)
            fail(at(), "face " + std::to_string(f) + " colour count " + std::to_string(colours) + " is not 0 to 4");
        for (std::int32_t j = 0; j < colours; ++j) word("a face colour");
        add_fan(soup, ids.data(), ids.size());
    }
}

}  // namespace

TriMesh read_off(const std::string& path, std::string_view bytes) {
    const OffHeader h = parse_header(path, bytes);
    TriMesh soup;
    soup.positions.reserve(static_cast<std::size_t>(h.vertices));
    if (h.binary) read_binary(path, bytes, h, soup);
    else read_ascii(path, bytes, h, soup);
    return soup;
}

}  // namespace tridex::compute
