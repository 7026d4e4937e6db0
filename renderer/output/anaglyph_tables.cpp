// renderer/output/anaglyph_tables.cpp - Dubois matrices, sRGB decode table and exact 8-bit sRGB encoding.
#include "renderer/output/anaglyph_tables.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace tridex::renderer {
namespace {

/// sRGB decoding (IEC 61966-2-1) of a value 0..1, linear light 0..1.
double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

/// The code tables and a 2^16-bin index giving, at each bin's start, the number of thresholds <= it.
/// Thresholds are >= 3e-4 apart (the steepest part of the curve, slope 12.92 near 0) and a bin is 1.5e-5
/// wide, so a bin holds at most one threshold: one compare after the lookup gives the exact count.
struct Tables {
    static constexpr int kBins = 1 << 16;
    SrgbCodeTables codes;
    std::vector<std::uint8_t> code_at_bin;
    Tables() : code_at_bin(kBins + 1) {
        for (int i = 0; i < 256; ++i) codes.to_linear[i] = srgb_to_linear(i / 255.0);
        for (int k = 0; k < 255; ++k) codes.thresholds[k] = srgb_to_linear((k + 0.5) / 255.0);
        const auto& t = codes.thresholds;
        for (int b = 0; b <= kBins; ++b)
            code_at_bin[b] =
                static_cast<std::uint8_t>(std::upper_bound(t.begin(), t.end(), static_cast<double>(b) / kBins) - t.begin());
    }
};

const Tables& tables() {
    static const Tables t;
    return t;
}

}  // namespace

const AnaglyphMatrices& dubois_matrices() {
    static const AnaglyphMatrices m{{{0.456100, 0.500484, 0.176381},
                                     {-0.0400822, -0.0378246, -0.0157589},
                                     {-0.0152161, -0.0205971, -0.00546856}},
                                    {{-0.0434706, -0.0879388, -0.00155529},
                                     {0.378476, 0.73364, -0.0184503},
                                     {-0.0721527, -0.112961, 1.2264}}};
    return m;
}

const SrgbCodeTables& srgb_code_tables() { return tables().codes; }

std::uint8_t srgb_encode_code(double v) {
    if (!(v > 0.0)) return 0;
    if (v >= 1.0) return 255;
    const Tables& t = tables();
    std::uint8_t code = t.code_at_bin[static_cast<int>(v * Tables::kBins)];
    if (code < 255 && v >= t.codes.thresholds[code]) ++code;
    return code;
}

}  // namespace tridex::renderer
