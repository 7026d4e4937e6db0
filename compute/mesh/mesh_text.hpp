// compute/mesh/mesh_text.hpp - what the OFF and PLY readers share: a file's bytes, a token scanner that knows its
// line, strict number parsing and big- or little-endian loads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace tridex::compute {

/// Every byte of the regular file `path`. Throws tridex::Error "<path>: cannot open file for reading" or
/// "<path>: read failed after N of M bytes".
std::string read_file_bytes(const std::string& path);

/// Whitespace-separated tokens of text in memory, from a byte offset on, with the line number of each token
/// (1-based, counted from the start of the text). With `hash_comments`, '#' starts a comment to the end of its line.
class TextScanner {
public:
    /// Scans `text` (which must outlive the scanner) from byte `offset`.
    TextScanner(std::string_view text, std::size_t offset, bool hash_comments);
    /// The next token, or an empty view at the end of the text.
    std::string_view next();
    /// The next token on the current line, or an empty view when the line (or the text) ends first; the scanner
    /// then stays before the newline.
    std::string_view next_on_line();
    /// Skips to the start of the next line.
    void skip_line();
    /// Line of the token last returned (or of the scan position before any).
    std::size_t line() const { return token_line_; }
    /// Bytes not yet scanned.
    std::size_t remaining() const { return text_.size() - pos_; }
    /// Byte offset of the scan position.
    std::size_t offset() const { return pos_; }

private:
    void skip_blanks(bool stop_at_newline);

    std::string_view text_;
    std::size_t pos_;
    std::size_t line_ = 1;
    std::size_t token_line_ = 1;
    bool hash_comments_;
};

/// Parses the whole of `token` as a decimal integer (an optional sign, digits); false when it is not one or does
/// not fit in 64 bits.
bool parse_whole_i64(std::string_view token, std::int64_t& out);

/// Parses the whole of `token` as a decimal floating-point number ("1", "-2.5e3"; also "nan" and "inf", which the
/// caller refuses as not finite); false when it is not one or is out of double's range ("1e999").
bool parse_whole_double(std::string_view token, double& out);

/// Unsigned integer of `size` bytes (1, 2, 4 or 8) at `p`, big-endian when `big_endian`, else little-endian.
std::uint64_t load_uint(const unsigned char* p, int size, bool big_endian);

}  // namespace tridex::compute
