// core/text/json_refusal.hpp - why a JSON text was refused, in one line that says where. nlohmann's parser places a syntax
// error by line and column itself, but reports a number beyond a double's range ("number overflow parsing '1e400'")
// with no place; parsing the text again with JsonPlaceFinder (a SAX handler) finds the line, the column and the field.
// Header-only and written against any nlohmann::basic_json type `Json` given as a template argument, so that core/
// includes no JSON library: each reader (scene, display config, bindings, ...) passes the one it parsed with.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/text/printable.hpp"

namespace tridex {

/// Where a JSON parser stopped.
struct JsonPlace {
    std::size_t line = 0;    ///< 1-based line of the refused token; 0 when the text parsed
    std::size_t column = 0;  ///< 1-based column (bytes) of the token's first character
    std::string field;       ///< path of the value being read: "workpiece.stock_m", "objects[2]"; "" at the top level
};

/// A SAX handler for Json::sax_parse that follows the path of the value being read and records the place of the
/// parser's error (place()). It builds nothing; `text` is the text being parsed, which must outlive the finder.
template <class Json>
class JsonPlaceFinder {
public:
    using string_t = typename Json::string_t;

    explicit JsonPlaceFinder(const std::string& text) : text_(text) {}

    bool null() { return value(); }
    bool boolean(bool) { return value(); }
    bool number_integer(typename Json::number_integer_t) { return value(); }
    bool number_unsigned(typename Json::number_unsigned_t) { return value(); }
    bool number_float(typename Json::number_float_t, const string_t&) { return value(); }
    bool string(string_t&) { return value(); }
    bool binary(typename Json::binary_t&) { return value(); }
    bool start_object(std::size_t) {
        levels_.push_back({false, 0, {}});
        return true;
    }
    bool key(string_t& k) {
        levels_.back().key = k;
        return true;
    }
    bool end_object() {
        levels_.pop_back();
        return value();
    }
    bool start_array(std::size_t) {
        levels_.push_back({true, 0, {}});
        return true;
    }
    bool end_array() {
        levels_.pop_back();
        return value();
    }
    /// Records the place: `position` is the offset just past the refused token `last_token`.
    bool parse_error(std::size_t position, const std::string& last_token, const typename Json::exception&) {
        const std::size_t end = position < text_.size() ? position : text_.size();
        const std::size_t start = last_token.size() <= end ? end - last_token.size() : 0;
        place_.line = 1;
        std::size_t line_start = 0;
        for (std::size_t i = 0; i < start; ++i)
            if (text_[i] == '\n') ++place_.line, line_start = i + 1;
        place_.column = start - line_start + 1;
        for (const Level& l : levels_) {
            if (l.array) place_.field += "[" + std::to_string(l.index) + "]";
            else place_.field += (place_.field.empty() ? "" : ".") + l.key;
        }
        return false;
    }

    /// Where the parse stopped (line 0 when it did not).
    const JsonPlace& place() const { return place_; }

private:
    struct Level {
        bool array = false;
        std::size_t index = 0;  ///< arrays: the element being read
        std::string key;        ///< objects: the key of the member being read
    };
    bool value() {
        if (!levels_.empty() && levels_.back().array) ++levels_.back().index;
        return true;
    }

    const std::string& text_;
    std::vector<Level> levels_;
    JsonPlace place_;
};

/// Where Json's parser stops on `text`: line 0 when the text parses.
template <class Json>
JsonPlace json_error_place(const std::string& text) {
    JsonPlaceFinder<Json> finder(text);
    const bool parsed = Json::sax_parse(text, &finder);  // false at the error, which the finder has placed
    (void)parsed;
    return finder.place();
}

/// Why Json's parser refused `text` with `e`, in one printable line: nlohmann's own reason without its
/// "[json.exception.*] " prefix (a syntax error's names its line and column: "parse error at line 3, column 5: syntax
/// error while parsing object - unexpected string literal; expected '}'"), except for a number beyond a double's range,
/// which is placed by JsonPlaceFinder: "number overflow at line 2, column 28, field 'workpiece.stock_m': '1e400' is
/// beyond a double's range (magnitudes up to about 1.8e308)".
template <class Json>
std::string json_refusal(const std::string& text, const typename Json::exception& e) {
    constexpr int kNumberOverflow = 406;  // nlohmann's out_of_range.406
    const std::string what = e.what();
    const std::size_t tag = what.find("] ");
    const std::string reason = tag == std::string::npos ? what : what.substr(tag + 2);
    if (e.id != kNumberOverflow) return printable(reason, 240);
    const JsonPlace at = json_error_place<Json>(text);
    if (at.line == 0) return printable(reason, 240);
    const std::size_t quote = reason.find('\'');
    const std::string token = quote == std::string::npos ? "" : reason.substr(quote + 1, reason.size() - quote - 2);
    return "number overflow at line " + std::to_string(at.line) + ", column " + std::to_string(at.column) +
           (at.field.empty() ? std::string(", the top-level value") : ", field '" + printable(at.field, 120) + "'") +
           ": '" + printable(token, 40) + "' is beyond a double's range (magnitudes up to about 1.8e308)";
}

}  // namespace tridex
