// core/crc32.hpp - the CRC-32 checksum every on-disk format of tridex uses.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tridex {

/// CRC-32 (IEEE 802.3 polynomial 0x04C11DB7, reflected, initial and final XOR 0xFFFFFFFF) of n bytes,
/// continuing from a previous result `crc` (0 to start). crc32_ieee("123456789") = 0xCBF43926.
std::uint32_t crc32_ieee(const void* data, std::size_t n, std::uint32_t crc = 0);

}  // namespace tridex
