// devices/net/wire_io.hpp - bounds-checked little-endian writer and reader over byte vectors (link datagrams).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/le_bytes.hpp"
#include "core/math.hpp"

namespace tridex::devices::net {

/// Appends little-endian values to a byte vector.
class Writer {
public:
    /// Appends to out (not cleared).
    explicit Writer(std::vector<std::uint8_t>& out) : out_(out) {}
    void u8(std::uint8_t v) { out_.push_back(v); }
    void u16(std::uint16_t v) {
        out_.push_back(static_cast<std::uint8_t>(v));
        out_.push_back(static_cast<std::uint8_t>(v >> 8));
    }
    void u32(std::uint32_t v) { put(v, 4); }
    void u64(std::uint64_t v) { put(v, 8); }
    void f32(float v) { u32(std::bit_cast<std::uint32_t>(v)); }
    void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
    void vec3(const Vec3& v) {
        f64(v.x);
        f64(v.y);
        f64(v.z);
    }
    void quat(const Quat& q) {
        f64(q.w);
        f64(q.x);
        f64(q.y);
        f64(q.z);
    }
    /// A u16 length, then the bytes.
    void str(const std::string& s) {
        u16(static_cast<std::uint16_t>(s.size()));
        out_.insert(out_.end(), s.begin(), s.end());
    }

private:
    void put(std::uint64_t v, int bytes) {
        for (int i = 0; i < bytes; ++i) out_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    }
    std::vector<std::uint8_t>& out_;
};

/// Reads little-endian values from a byte range; a read past the end returns 0 and sets failed(); a
/// non-finite f64/f32 sets non_finite() (the value is still returned).
class Reader {
public:
    Reader(const std::uint8_t* p, std::size_t n) : p_(p), n_(n) {}
    std::uint8_t u8() { return take(1) ? p_[pos_ - 1] : 0; }
    std::uint16_t u16() { return take(2) ? static_cast<std::uint16_t>(p_[pos_ - 2] | (p_[pos_ - 1] << 8)) : 0; }
    std::uint32_t u32() { return take(4) ? get_u32(p_ + pos_ - 4) : 0; }
    std::uint64_t u64() { return take(8) ? get_u64(p_ + pos_ - 8) : 0; }
    float f32() {
        const float v = std::bit_cast<float>(u32());
        if (!std::isfinite(v)) non_finite_ = true;
        return v;
    }
    double f64() {
        const double v = std::bit_cast<double>(u64());
        if (!std::isfinite(v)) non_finite_ = true;
        return v;
    }
    Vec3 vec3() {
        const double x = f64(), y = f64(), z = f64();
        return Vec3(x, y, z);
    }
    Quat quat() {
        const double w = f64(), x = f64(), y = f64(), z = f64();
        return Quat(w, x, y, z);
    }
    /// A u16 length (at most max_len, else failed()), then the bytes.
    std::string str(std::size_t max_len) {
        const std::size_t len = u16();
        if (len > max_len || !take(len)) {
            failed_ = true;
            return {};
        }
        return std::string(reinterpret_cast<const char*>(p_ + pos_ - len), len);
    }
    /// The next n bytes, in place (valid while the range is); nullptr and failed() when fewer remain.
    const std::uint8_t* bytes(std::size_t n) { return take(n) ? p_ + pos_ - n : nullptr; }
    bool failed() const { return failed_; }
    bool non_finite() const { return non_finite_; }
    bool at_end() const { return pos_ == n_; }
    std::size_t remaining() const { return n_ - pos_; }

private:
    bool take(std::size_t k) {
        if (failed_ || n_ - pos_ < k) {
            failed_ = true;
            return false;
        }
        pos_ += k;
        return true;
    }
    const std::uint8_t* p_;
    std::size_t n_;
    std::size_t pos_ = 0;
    bool failed_ = false;
    bool non_finite_ = false;
};

}  // namespace tridex::devices::net
