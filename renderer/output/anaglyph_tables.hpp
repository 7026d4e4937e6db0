// renderer/output/anaglyph_tables.hpp - the Dubois anaglyph's matrices and sRGB code tables, shared by CPU and GPU.
#pragma once

#include <array>
#include <cstdint>

namespace tridex::renderer {

/// Dubois' red-cyan least-squares matrices (E. Dubois, ICASSP 2001) for linear light: out = left * L + right * R,
/// row = output channel r, g, b; column = input channel r, g, b.
struct AnaglyphMatrices {
    double left[3][3];
    double right[3][3];
};

/// The matrices of AnaglyphMethod::kDubois.
const AnaglyphMatrices& dubois_matrices();

/// sRGB tables of the 8-bit codes (IEC 61966-2-1). `to_linear[c]` is code c decoded to linear light 0..1;
/// `thresholds[k]` = decode((k + 0.5) / 255) is the linear-light boundary between codes k and k + 1, so that
/// encoding linear v with rounding to the nearest code, round(encode(v) * 255), equals the number of
/// thresholds <= v (encode is monotonic).
struct SrgbCodeTables {
    std::array<double, 256> to_linear{};
    std::array<double, 255> thresholds{};
};

/// The tables (computed once, thread-safe).
const SrgbCodeTables& srgb_code_tables();

/// round(encode(v) * 255) for linear v, clamped to 0..255 (v <= 0 or NaN -> 0, v >= 1 -> 255), exact by
/// the thresholds of srgb_code_tables() (a 2^16-bin index and one compare).
std::uint8_t srgb_encode_code(double v);

}  // namespace tridex::renderer
