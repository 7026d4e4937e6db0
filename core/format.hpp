// core/format.hpp - numbers in messages as a person writes them.
#pragma once

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

}  // namespace tridex
