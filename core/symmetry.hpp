// core/symmetry.hpp - the sculpting symmetry a ToolSample carries: mirror planes or radial copies about the
// workpiece's centre. The poses themselves are computed in compute/tools/symmetry.hpp.
#pragma once

#include <cstdint>
#include <string>

namespace tridex {

/// Which symmetric copies of every operation the sculpt thread applies. The centre is always the workpiece
/// lattice's centre (known to whoever applies the samples), so a sample needs no more than this.
/// Either mirrors or radial copies, never both (the combined group could hold one pose twice, and a clay
/// operation applied twice at one pose is not the same as once). Trivially copyable (4 bytes), so a ToolSample
/// carrying it goes through the haptic thread's lock-free ring unchanged.
struct Symmetry {
    std::uint8_t mirrors = 0;         ///< bit 0: mirror across the plane x = centre.x; bit 1: y; bit 2: z
    std::uint8_t radial_axis = 0;     ///< 0 x, 1 y, 2 z: the axis (through the centre) of the radial copies
    std::uint16_t radial_copies = 0;  ///< 0 = no radial symmetry; else kMinRadialCopies..kMaxRadialCopies

    static constexpr std::uint8_t kMirrorX = 1, kMirrorY = 2, kMirrorZ = 4;
    static constexpr int kMinRadialCopies = 2;   ///< fewest radial copies (the tool itself counts as one)
    static constexpr int kMaxRadialCopies = 32;  ///< most radial copies

    /// True when any symmetry is on.
    bool on() const { return mirrors != 0 || radial_copies != 0; }
    /// How many poses one tool pose becomes: 2^(mirror planes), or radial_copies, or 1 when off.
    int copies() const;
    bool operator==(const Symmetry&) const = default;
};

/// The allowed spellings, for messages: "off, x, y, z, xy, xz, yz, xyz or radial:N:AXIS (N 2..32, AXIS x, y or z)".
const char* symmetry_forms();

/// The symmetry as the option and scene field spell it: "off", "x", "xz", "xyz", "radial:6:z".
std::string to_string(const Symmetry& s);

/// Inverse of to_string: "off" (or "none"), a non-empty set of the letters x, y, z each at most once in the
/// order x, y, z, or "radial:N:AXIS". Throws tridex::Error "<what>: bad symmetry 'v'; use <symmetry_forms()>"
/// naming `what` (e.g. "--symmetry") and, for a radial count out of range, the range.
Symmetry parse_symmetry(const std::string& text, const std::string& what);

/// True when `s` is a value parse_symmetry can return (mirror bits only 0..2, radial copies 0 or 2..32, axis 0..2
/// and 0 when there are no radial copies, not both mirrors and radial copies).
bool valid_symmetry(const Symmetry& s);

/// Packs `s` into 32 bits (mirrors | radial_axis << 8 | radial_copies << 16), for an atomic hand-off.
inline std::uint32_t symmetry_bits(const Symmetry& s) {
    return std::uint32_t{s.mirrors} | std::uint32_t{s.radial_axis} << 8 | std::uint32_t{s.radial_copies} << 16;
}

/// Inverse of symmetry_bits.
inline Symmetry symmetry_from_bits(std::uint32_t b) {
    return Symmetry{static_cast<std::uint8_t>(b & 0xffu), static_cast<std::uint8_t>((b >> 8) & 0xffu),
                    static_cast<std::uint16_t>(b >> 16)};
}

}  // namespace tridex
