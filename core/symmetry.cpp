// core/symmetry.cpp - symmetry names and checks.
#include "core/symmetry.hpp"

#include "core/error.hpp"

namespace tridex {

int Symmetry::copies() const {
    if (radial_copies != 0) return radial_copies;
    int n = 1;
    for (int a = 0; a < 3; ++a)
        if (mirrors & (1u << a)) n *= 2;
    return n;
}

const char* symmetry_forms() { return "off, x, y, z, xy, xz, yz, xyz or radial:N:AXIS (N 2..32, AXIS x, y or z)"; }

std::string to_string(const Symmetry& s) {
    if (s.radial_copies != 0)
        return "radial:" + std::to_string(s.radial_copies) + ":" +
               (s.radial_axis < 3 ? std::string(1, static_cast<char>('x' + s.radial_axis))
                                  : "axis" + std::to_string(s.radial_axis));
    if (s.mirrors == 0) return "off";
    std::string out;
    for (int a = 0; a < 3; ++a)
        if (s.mirrors & (1u << a)) out += static_cast<char>('x' + a);
    return out;
}

namespace {

[[noreturn]] void bad(const std::string& text, const std::string& what, const std::string& why = "") {
    throw Error(what + ": bad symmetry '" + text + "'" + (why.empty() ? "" : " (" + why + ")") + "; use " +
                symmetry_forms());
}

int axis_of(char c) { return c == 'x' ? 0 : c == 'y' ? 1 : c == 'z' ? 2 : -1; }

Symmetry parse_radial(const std::string& text, const std::string& what) {
    const std::string rest = text.substr(7);  // after "radial:"
    const std::size_t colon = rest.find(':');
    if (colon == std::string::npos || colon == 0 || colon + 2 != rest.size()) bad(text, what);
    const std::string count = rest.substr(0, colon);
    if (count.size() > 3 || count.find_first_not_of("0123456789") != std::string::npos) bad(text, what);
    const int n = std::stoi(count);
    if (n < Symmetry::kMinRadialCopies || n > Symmetry::kMaxRadialCopies)
        bad(text, what, "N = " + count + " is outside 2..32");
    const int axis = axis_of(rest.back());
    if (axis < 0) bad(text, what, "the axis must be x, y or z");
    Symmetry s;
    s.radial_copies = static_cast<std::uint16_t>(n);
    s.radial_axis = static_cast<std::uint8_t>(axis);
    return s;
}

}  // namespace

Symmetry parse_symmetry(const std::string& text, const std::string& what) {
    if (text == "off" || text == "none") return Symmetry{};
    if (text.rfind("radial:", 0) == 0) return parse_radial(text, what);
    if (text.empty() || text.size() > 3) bad(text, what);
    Symmetry s;
    int last = -1;
    for (char c : text) {
        const int a = axis_of(c);
        if (a <= last) bad(text, what);  // unknown letter, repeated or out of order
        s.mirrors = static_cast<std::uint8_t>(s.mirrors | (1u << a));
        last = a;
    }
    return s;
}

bool valid_symmetry(const Symmetry& s) {
    if (s.mirrors > 7 || s.radial_axis > 2) return false;
    if (s.radial_copies == 0) return s.radial_axis == 0;
    return s.mirrors == 0 && s.radial_copies >= Symmetry::kMinRadialCopies &&
           s.radial_copies <= Symmetry::kMaxRadialCopies;
}

}  // namespace tridex
