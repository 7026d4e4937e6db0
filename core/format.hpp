// core/format.hpp - numbers in messages as a person writes them.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

namespace tridex {

/// `v` with up to 6 significant digits and no trailing zeros ("75", "0.5", "1e+308", "inf", "nan"), for error
/// messages and notes (std::to_string gives "75.000000").
inline std::string format_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

/// `v` with exactly `digits` digits after the point ("0.968", "-0.08"), for figures a message lines up.
inline std::string format_fixed(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

/// A length `m` (metres) in millimetres to a tenth of a millimetre, as a person reads it on screen: "11.7 mm",
/// "12 mm" (no trailing ".0"), "0 mm" (never "-0" nor "8.67e-16"); a non-finite length gives "-- mm".
inline std::string format_mm(double m) {
    const double mm = std::round(m * 1e4) / 10.0;  // tenths of a millimetre
    if (!std::isfinite(mm)) return "-- mm";
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.1f", mm == 0.0 ? 0.0 : mm);
    std::string s = buf;
    if (s.size() > 2 && s.compare(s.size() - 2, 2, ".0") == 0) s.resize(s.size() - 2);
    return s + " mm";
}

}  // namespace tridex
