// core/text/printable.hpp - text taken from a file, made safe to quote in a one-line message.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace tridex {

/// `text` as it may appear inside quotes in an error message: printable ASCII is kept, every other byte
/// (control characters, newlines, escape sequences, non-ASCII) becomes "\xNN", and text longer than
/// `max_chars` input bytes is cut there and ends in "...". Never throws (but std::bad_alloc).
inline std::string printable(std::string_view text, std::size_t max_chars = 32) {
    static constexpr char kHex[] = "0123456789abcdef";
    std::string out;
    const std::size_t n = text.size() < max_chars ? text.size() : max_chars;
    out.reserve(n + 3);
    for (std::size_t i = 0; i < n; ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        if (c >= 0x20 && c < 0x7f && c != '\\') {
            out.push_back(static_cast<char>(c));
        } else if (c == '\\') {
            out += "\\\\";
        } else {
            out += "\\x";
            out.push_back(kHex[c >> 4]);
            out.push_back(kHex[c & 15]);
        }
    }
    if (text.size() > max_chars) out += "...";
    return out;
}

}  // namespace tridex
