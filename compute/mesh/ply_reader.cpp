// compute/mesh/ply_reader.cpp - PLY (ASCII, binary little- and big-endian) into a polygon soup, strictly.
#include "compute/mesh/ply_reader.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "compute/mesh/mesh_text.hpp"
#include "core/error.hpp"
#include "core/text/printable.hpp"

namespace tridex::compute {
namespace {

using u128 = unsigned __int128;

[[noreturn]] void fail(const std::string& where, const std::string& reason) { throw Error(where + ": " + reason); }

std::string quoted(std::string_view token) { return "'" + printable(token) + "'"; }

enum class Type { kNone, kI8, kU8, kI16, kU16, kI32, kU32, kF32, kF64 };

Type type_named(std::string_view t) {
    if (t == "char" || t == "int8") return Type::kI8;
    if (t == "uchar" || t == "uint8") return Type::kU8;
    if (t == "short" || t == "int16") return Type::kI16;
    if (t == "ushort" || t == "uint16") return Type::kU16;
    if (t == "int" || t == "int32") return Type::kI32;
    if (t == "uint" || t == "uint32") return Type::kU32;
    if (t == "float" || t == "float32") return Type::kF32;
    if (t == "double" || t == "float64") return Type::kF64;
    return Type::kNone;
}

int size_of(Type t) {
    switch (t) {
        case Type::kI8: case Type::kU8: return 1;
        case Type::kI16: case Type::kU16: return 2;
        case Type::kI32: case Type::kU32: case Type::kF32: return 4;
        case Type::kF64: return 8;
        case Type::kNone: break;
    }
    return 0;
}

bool is_integral(Type t) { return t != Type::kF32 && t != Type::kF64 && t != Type::kNone; }

/// The range of an integral type.
void integral_range(Type t, std::int64_t& lo, std::int64_t& hi) {
    const int bits = 8 * size_of(t);
    const bool is_signed = t == Type::kI8 || t == Type::kI16 || t == Type::kI32;
    lo = is_signed ? -(std::int64_t{1} << (bits - 1)) : 0;
    hi = is_signed ? (std::int64_t{1} << (bits - 1)) - 1 : (std::int64_t{1} << bits) - 1;
}

struct Property {
    std::string name;
    Type type = Type::kNone;        ///< scalar type, or the item type of a list
    Type count_type = Type::kNone;  ///< a list's count type; kNone for a scalar
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> properties;
};

struct Header {
    enum class Format { kAscii, kLittle, kBig } format = Format::kAscii;
    std::vector<Element> elements;
    std::size_t body = 0;  ///< byte offset after the end_header line
    int vertex = -1, face = -1;        ///< element indices
    int x = -1, y = -1, z = -1;        ///< property indices in the vertex element
    int indices = -1;                  ///< the list property in the face element
};

/// Words of one header line.
std::vector<std::string_view> words_of(std::string_view line) {
    std::vector<std::string_view> w;
    TextScanner s(line, 0, false);
    for (std::string_view t = s.next(); !t.empty(); t = s.next()) w.push_back(t);
    return w;
}

void parse_property(const std::vector<std::string_view>& w, Header& h, const std::string& at) {
    if (h.elements.empty()) fail(at, "PLY header: a property before any element");
    Property p;
    if (w.size() >= 2 && w[1] == "list") {
        if (w.size() != 5) fail(at, "PLY header: a list property needs 'property list COUNT_TYPE ITEM_TYPE NAME'");
        p.count_type = type_named(w[2]);
        p.type = type_named(w[3]);
        if (!is_integral(p.count_type) || p.type == Type::kNone)
            fail(at, "PLY header: bad list property types " + quoted(std::string(w[2]) + " " + std::string(w[3])) +
                         " (the count must be an integer type)");
        p.name = w[4];
    } else {
        if (w.size() != 3) fail(at, "PLY header: a property needs 'property TYPE NAME'");
        p.type = type_named(w[1]);
        if (p.type == Type::kNone) fail(at, "PLY header: unknown property type " + quoted(w[1]));
        p.name = w[2];
    }
    h.elements.back().properties.push_back(p);
}

/// Finds the vertex and face elements and their x, y, z and index-list properties.
void find_mesh_properties(const std::string& path, Header& h) {
    for (std::size_t e = 0; e < h.elements.size(); ++e) {
        const auto& props = h.elements[e].properties;
        if (h.elements[e].name == "vertex" && h.vertex < 0) {
            h.vertex = static_cast<int>(e);
            for (std::size_t k = 0; k < props.size(); ++k) {
                if (props[k].count_type != Type::kNone) continue;
                if (props[k].name == "x") h.x = static_cast<int>(k);
                if (props[k].name == "y") h.y = static_cast<int>(k);
                if (props[k].name == "z") h.z = static_cast<int>(k);
            }
        } else if (h.elements[e].name == "face" && h.face < 0) {
            h.face = static_cast<int>(e);
            for (std::size_t k = 0; k < props.size(); ++k)
                if (props[k].count_type != Type::kNone && (props[k].name == "vertex_indices" || props[k].name == "vertex_index"))
                    h.indices = static_cast<int>(k);
        }
    }
    if (h.vertex < 0 || h.x < 0 || h.y < 0 || h.z < 0)
        fail(path, "PLY header: no element 'vertex' with properties x, y and z");
    if (h.face < 0 || h.indices < 0)
        fail(path, "PLY header: no element 'face' with a list property 'vertex_indices'");
    if (!is_integral(h.elements[h.face].properties[h.indices].type))
        fail(path, "PLY header: the face list 'vertex_indices' has a non-integer item type");
}

Header parse_header(const std::string& path, std::string_view bytes) {
    Header h;
    std::size_t pos = 0, line_no = 0;
    bool have_format = false, have_end = false;
    while (pos < bytes.size() && pos < (std::size_t{1} << 20)) {
        std::size_t end = bytes.find('\n', pos);
        if (end == std::string_view::npos) end = bytes.size();
        std::string_view line = bytes.substr(pos, end - pos);
        pos = end + 1;
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        const std::string at = path + ":" + std::to_string(line_no);
        if (line_no == 1) {
            if (line != "ply") fail(path, "not a PLY file (missing 'ply' magic line)");
            continue;
        }
        const auto w = words_of(line);
        if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
        if (w[0] == "end_header") {
            have_end = true;
            break;
        }
        if (w[0] == "format") {
            if (have_format) fail(at, "PLY header: a second format line");
            if (!h.elements.empty()) fail(at, "PLY header: the format line comes after an element");
            if (w.size() != 3) fail(at, "PLY header: the format line needs 'format KIND 1.0'");
            if (w[1] == "ascii") h.format = Header::Format::kAscii;
            else if (w[1] == "binary_little_endian") h.format = Header::Format::kLittle;
            else if (w[1] == "binary_big_endian") h.format = Header::Format::kBig;
            else fail(at, "PLY header: unknown format " + quoted(w[1]));
            if (w[2] != "1.0") fail(at, "PLY header: unknown version " + quoted(w[2]) + " (expected 1.0)");
            have_format = true;
        } else if (w[0] == "element") {
            if (!have_format) fail(at, "PLY header has no format line before its first element");
            std::int64_t n = 0;
            if (w.size() != 3 || !parse_whole_i64(w[2], n) || n < 0)
                fail(at, "PLY header: element " + quoted(w.size() > 1 ? w[1] : "") + " count " +
                             quoted(w.size() > 2 ? w[2] : "") + " is not a non-negative integer");
            h.elements.push_back({std::string(w[1]), static_cast<std::uint64_t>(n), {}});
        } else if (w[0] == "property") {
            parse_property(w, h, at);
        }  // any other line is free text, as some exporters write (Blender 2.4: "Created by Blender3D ...")
    }
    if (!have_end) fail(path, "PLY header has no end_header line");
    if (!have_format) fail(path, "PLY header has no format line");
    h.body = pos < bytes.size() ? pos : bytes.size();
    // The least the body can hold: ASCII two bytes a number (one less for the last), binary each scalar's size and
    // each list's count.
    const bool binary = h.format != Header::Format::kAscii;
    u128 need = 0;
    for (const Element& e : h.elements) {
        u128 one = 0;
        for (const Property& p : e.properties) one += binary ? size_of(p.count_type != Type::kNone ? p.count_type : p.type) : 2;
        need += one * e.count;
    }
    if (!binary && need > 0) need -= 1;
    if (need > bytes.size() - h.body)
        fail(path, "PLY header declares more elements than a file of " + std::to_string(bytes.size()) + " bytes can hold");
    find_mesh_properties(path, h);
    if (h.elements[h.vertex].count > 0xffffffffull || h.elements[h.face].count > 0xffffffffull)
        fail(path, "PLY header counts exceed 32-bit indices");
    return h;
}

/// Where the reader is, for messages; reads one number of a type in ASCII or binary.
class Body {
public:
    Body(const std::string& path, std::string_view bytes, const Header& h)
        : path_(path), bytes_(bytes), binary_(h.format != Header::Format::kAscii), big_(h.format == Header::Format::kBig),
          text_(bytes, h.body, false), pos_(h.body) {}

    std::string at() const {
        return binary_ ? path_ + ": byte " + std::to_string(pos_) : path_ + ":" + std::to_string(text_.line());
    }
    std::size_t remaining() const { return binary_ ? bytes_.size() - pos_ : text_.remaining(); }
    bool binary() const { return binary_; }

    /// The next number of type `t`; `what()` names it in a refusal (built only then).
    template <class What>
    double number(Type t, const What& what) {
        if (binary_) return binary_number(t, what);
        const std::string_view tok = text_.next();
        if (tok.empty()) fail(at(), "the file ends in " + what());
        if (is_integral(t)) {
            std::int64_t v = 0, lo = 0, hi = 0;
            integral_range(t, lo, hi);
            if (!parse_whole_i64(tok, v) || v < lo || v > hi)
                fail(at(), what() + " " + quoted(tok) + " is not an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
            return static_cast<double>(v);
        }
        double v = 0.0;
        if (!parse_whole_double(tok, v)) fail(at(), what() + " " + quoted(tok) + " is not a number");
        return v;
    }

private:
    template <class What>
    double binary_number(Type t, const What& what) {
        const int n = size_of(t);
        if (bytes_.size() - pos_ < static_cast<std::size_t>(n)) fail(at(), "the file ends in " + what());
        const std::uint64_t u = load_uint(reinterpret_cast<const unsigned char*>(bytes_.data()) + pos_, n, big_);
        pos_ += static_cast<std::size_t>(n);
        switch (t) {
            case Type::kI8: return static_cast<std::int8_t>(u);
            case Type::kI16: return static_cast<std::int16_t>(u);
            case Type::kI32: return static_cast<std::int32_t>(u);
            case Type::kF32: return std::bit_cast<float>(static_cast<std::uint32_t>(u));
            case Type::kF64: return std::bit_cast<double>(u);
            default: return static_cast<double>(u);
        }
    }

    const std::string& path_;
    std::string_view bytes_;
    bool binary_, big_;
    TextScanner text_;
    std::size_t pos_;
};

/// Adds the fan triangles of one face whose indices were checked.
void add_fan(TriMesh& soup, const std::vector<std::uint32_t>& ids) {
    for (std::size_t j = 1; j + 1 < ids.size(); ++j) soup.triangles.push_back({ids[0], ids[j], ids[j + 1]});
}

/// Reads a list property's count and items; keeps the items in `ids` (checked as vertex indices) when `face_list`.
void read_list(Body& body, const Property& p, std::uint64_t i, bool face_list, std::uint64_t nv,
               std::vector<std::uint32_t>& ids, const std::function<std::string()>& what) {
    const double n = body.number(p.count_type, [&] { return what() + " count"; });
    if (n < 0) fail(body.at(), what() + " count " + std::to_string(static_cast<std::int64_t>(n)) + " is negative");
    const auto count = static_cast<std::uint64_t>(n);
    const std::uint64_t least = body.binary() ? count * static_cast<std::uint64_t>(size_of(p.type)) : 2 * count - 1;
    if (count > 0 && least > body.remaining())
        fail(body.at(), what() + " claims " + std::to_string(count) + " items, more than the " +
                            std::to_string(body.remaining()) + " bytes left can hold");
    if (face_list && count < 3)
        fail(body.at(), "face " + std::to_string(i) + " has " + std::to_string(count) + " vertices (needs at least 3)");
    if (face_list) ids.resize(static_cast<std::size_t>(count));
    for (std::uint64_t j = 0; j < count; ++j) {
        const double v = body.number(p.type, [&] { return what() + " item " + std::to_string(j); });
        if (!face_list) continue;
        if (v < 0 || v >= static_cast<double>(nv))
            fail(body.at(), "face " + std::to_string(i) + " vertex index " + std::to_string(static_cast<std::int64_t>(v)) +
                                " is not in 0.." + std::to_string(static_cast<std::int64_t>(nv) - 1));
        ids[static_cast<std::size_t>(j)] = static_cast<std::uint32_t>(v);
    }
}

void read_element(Body& body, const Header& h, int e, TriMesh& soup) {
    const Element& el = h.elements[static_cast<std::size_t>(e)];
    const auto nv = h.elements[static_cast<std::size_t>(h.vertex)].count;
    std::vector<std::uint32_t> ids;
    double xyz[3] = {0, 0, 0};
    for (std::uint64_t i = 0; i < el.count; ++i) {
        for (std::size_t k = 0; k < el.properties.size(); ++k) {
            const Property& p = el.properties[k];
            const auto what = [&] { return printable(el.name) + " " + std::to_string(i) + " property '" + printable(p.name) + "'"; };
            if (p.count_type != Type::kNone) {
                const bool face_list = e == h.face && static_cast<int>(k) == h.indices;
                read_list(body, p, i, face_list, nv, ids, what);
                if (face_list) add_fan(soup, ids);
                continue;
            }
            const double v = body.number(p.type, what);
            const int kk = static_cast<int>(k);
            const int axis = e != h.vertex ? -1 : kk == h.x ? 0 : kk == h.y ? 1 : kk == h.z ? 2 : -1;
            if (axis < 0) continue;
            if (!body.binary() && !std::isfinite(v)) fail(body.at(), what() + " is not a finite number");
            xyz[axis] = v;
        }
        if (e == h.vertex) soup.positions.push_back(Vec3(xyz[0], xyz[1], xyz[2]));
    }
}

}  // namespace

TriMesh read_ply(const std::string& path, std::string_view bytes) {
    const Header h = parse_header(path, bytes);
    TriMesh soup;
    soup.positions.reserve(static_cast<std::size_t>(h.elements[static_cast<std::size_t>(h.vertex)].count));
    Body body(path, bytes, h);
    for (std::size_t e = 0; e < h.elements.size(); ++e) read_element(body, h, static_cast<int>(e), soup);
    return soup;
}

}  // namespace tridex::compute
