// compute/mesh/mesh_text.cpp - file bytes, a line-aware token scanner and strict numbers for the mesh readers.
#include "compute/mesh/mesh_text.hpp"

#include <charconv>
#include <cstdio>
#include <memory>

#include "core/error.hpp"

namespace tridex::compute {

std::string read_file_bytes(const std::string& path) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!f) throw Error(path + ": cannot open file for reading");
    std::string bytes;
    char buf[1 << 16];
    std::size_t got;
    while ((got = std::fread(buf, 1, sizeof buf, f.get())) > 0) bytes.append(buf, got);
    if (std::ferror(f.get())) throw Error(path + ": read failed after " + std::to_string(bytes.size()) + " bytes");
    return bytes;
}

TextScanner::TextScanner(std::string_view text, std::size_t offset, bool hash_comments)
    : text_(text), pos_(offset < text.size() ? offset : text.size()), hash_comments_(hash_comments) {
    for (std::size_t i = 0; i < pos_; ++i) line_ += text_[i] == '\n';
    token_line_ = line_;
}

namespace {
bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
}  // namespace

void TextScanner::skip_blanks(bool stop_at_newline) {
    while (pos_ < text_.size()) {
        const char c = text_[pos_];
        if (c == '\n') {
            if (stop_at_newline) return;
            ++line_;
            ++pos_;
        } else if (is_blank(c)) {
            ++pos_;
        } else if (c == '#' && hash_comments_) {
            while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
        } else {
            return;
        }
    }
}

std::string_view TextScanner::next() {
    skip_blanks(false);
    token_line_ = line_;
    const std::size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n' && !is_blank(text_[pos_]) && !(hash_comments_ && text_[pos_] == '#'))
        ++pos_;
    return text_.substr(start, pos_ - start);
}

std::string_view TextScanner::next_on_line() {
    skip_blanks(true);
    if (pos_ >= text_.size() || text_[pos_] == '\n') return {};
    return next();
}

void TextScanner::skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    if (pos_ < text_.size()) {
        ++pos_;
        ++line_;
    }
}

bool parse_whole_i64(std::string_view token, std::int64_t& out) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty()) return false;
    const auto r = std::from_chars(token.data(), token.data() + token.size(), out);
    return r.ec == std::errc() && r.ptr == token.data() + token.size();
}

bool parse_whole_double(std::string_view token, double& out) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty()) return false;
    const auto r = std::from_chars(token.data(), token.data() + token.size(), out);
    return r.ec == std::errc() && r.ptr == token.data() + token.size();
}

std::uint64_t load_uint(const unsigned char* p, int size, bool big_endian) {
    std::uint64_t v = 0;
    for (int i = 0; i < size; ++i) {
        const int byte = big_endian ? i : size - 1 - i;
        v = (v << 8) | p[byte];
    }
    return v;
}

}  // namespace tridex::compute
