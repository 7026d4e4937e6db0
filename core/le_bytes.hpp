// core/le_bytes.hpp - little-endian integers in byte buffers, for tridex's binary files (journal, recording, meshes).
#pragma once

#include <bit>
#include <cstdint>

namespace tridex {

/// Writes v to p[0, 2) least significant byte first.
inline void put_u16(unsigned char* p, std::uint16_t v) {
    p[0] = static_cast<unsigned char>(v);
    p[1] = static_cast<unsigned char>(v >> 8);
}

/// Writes v to p[0, 4) least significant byte first (any host byte order).
inline void put_u32(unsigned char* p, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}

/// Writes v to p[0, 8) least significant byte first.
inline void put_u64(unsigned char* p, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}

/// Writes the IEEE-754 bits of v to p[0, 8), little-endian.
inline void put_f64(unsigned char* p, double v) { put_u64(p, std::bit_cast<std::uint64_t>(v)); }

/// Reads a little-endian u16 from p[0, 2).
inline std::uint16_t get_u16(const unsigned char* p) {
    return static_cast<std::uint16_t>(p[0] | static_cast<unsigned>(p[1]) << 8);
}

/// Reads a little-endian u32 from p[0, 4).
inline std::uint32_t get_u32(const unsigned char* p) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(p[i]) << (8 * i);
    return v;
}

/// Reads a little-endian u64 from p[0, 8).
inline std::uint64_t get_u64(const unsigned char* p) {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(p[i]) << (8 * i);
    return v;
}

/// Reads little-endian IEEE-754 bits from p[0, 8) as a double (bit for bit).
inline double get_f64(const unsigned char* p) { return std::bit_cast<double>(get_u64(p)); }

}  // namespace tridex
