// compute/history/undo_history_io.cpp - an undo history's steps as bytes, for a copy of the model elsewhere.
//
// Layout (little-endian): "TDXH", u32 version 1, u64 serial, u64 strokes, dropped_steps, oversize_strokes, undos,
// redos, u32 undo steps, u32 redo steps, then each step (undo steps oldest first, then redo steps oldest first):
// u64 serial, 6 x f64 box (lo, hi), u32 rays, and each ray: u8 axis, u32 index, u32 intervals, u32 capacity, and each
// interval: f32 enter, f32 exit, u8 enter material, u8 exit material.
#include "compute/history/undo_history.hpp"

#include <bit>
#include <cstring>
#include <string>

#include "core/error.hpp"
#include "core/le_bytes.hpp"

namespace tridex::compute {
namespace {

constexpr unsigned char kMagic[4] = {'T', 'D', 'X', 'H'};
constexpr std::uint32_t kVersion = 1;

class Out {
public:
    void u8(std::uint8_t v) { b_.push_back(v); }
    void u32(std::uint32_t v) { put(4, [&](unsigned char* p) { put_u32(p, v); }); }
    void u64(std::uint64_t v) { put(8, [&](unsigned char* p) { put_u64(p, v); }); }
    void f64(double v) { put(8, [&](unsigned char* p) { put_f64(p, v); }); }
    void f32(float v) { u32(std::bit_cast<std::uint32_t>(v)); }
    std::vector<unsigned char> take() { return std::move(b_); }

private:
    std::vector<unsigned char> b_;
    template <class F>
    void put(std::size_t n, F f) {
        b_.resize(b_.size() + n);
        f(b_.data() + b_.size() - n);
    }
};

class In {
public:
    explicit In(std::span<const unsigned char> b) : b_(b) {}
    const unsigned char* take(std::size_t n, const char* what) {
        if (b_.size() - at_ < n) throw Error(std::string("undo history bytes: truncated at ") + what);
        const unsigned char* p = b_.data() + at_;
        at_ += n;
        return p;
    }
    std::uint8_t u8(const char* w) { return *take(1, w); }
    std::uint32_t u32(const char* w) { return get_u32(take(4, w)); }
    std::uint64_t u64(const char* w) { return get_u64(take(8, w)); }
    double f64(const char* w) { return get_f64(take(8, w)); }
    float f32(const char* w) { return std::bit_cast<float>(u32(w)); }
    bool done() const { return at_ == b_.size(); }

private:
    std::span<const unsigned char> b_;
    std::size_t at_ = 0;
};

}  // namespace

std::vector<unsigned char> UndoHistory::save_steps() const {
    if (open_) throw Error("undo history: a stroke is open; close it before saving the steps");
    Out o;
    for (const unsigned char c : kMagic) o.u8(c);
    o.u32(kVersion);
    o.u64(serial_);
    for (const std::uint64_t c : {counts_.strokes, counts_.dropped_steps, counts_.oversize_strokes, counts_.undos, counts_.redos})
        o.u64(c);
    o.u32(static_cast<std::uint32_t>(undo_.size()));
    o.u32(static_cast<std::uint32_t>(redo_.size()));
    for (const std::deque<Step>* steps : {&undo_, &redo_})
        for (const Step& s : *steps) {
            o.u64(s.serial);
            for (const Vec3& v : {s.box_m.lo, s.box_m.hi})
                for (int k = 0; k < 3; ++k) o.f64(v[k]);
            o.u32(static_cast<std::uint32_t>(s.rays.size()));
            for (const RayImage& r : s.rays) {
                o.u8(r.axis);
                o.u32(r.index);
                o.u32(static_cast<std::uint32_t>(r.intervals.size()));
                o.u32(static_cast<std::uint32_t>(r.intervals.capacity()));
                for (const Interval& iv : r.intervals) {
                    o.f32(iv.enter);
                    o.f32(iv.exit);
                    o.u8(iv.enter_material);
                    o.u8(iv.exit_material);
                }
            }
        }
    return o.take();
}

void UndoHistory::load_steps(std::span<const unsigned char> bytes) {
    if (open_) throw Error("undo history: a stroke is open; the steps cannot be replaced");
    In in(bytes);
    if (std::memcmp(in.take(4, "the magic"), kMagic, 4) != 0) throw Error("undo history bytes: not an undo history");
    if (const std::uint32_t v = in.u32("the version"); v != kVersion)
        throw Error("undo history bytes: version " + std::to_string(v) + ", this build reads " + std::to_string(kVersion));
    const std::uint64_t serial = in.u64("the serial");
    HistoryStats counts = counts_;
    for (std::uint64_t* c : {&counts.strokes, &counts.dropped_steps, &counts.oversize_strokes, &counts.undos, &counts.redos})
        *c = in.u64("the counters");
    const std::uint32_t n_undo = in.u32("the step count"), n_redo = in.u32("the step count");
    std::deque<Step> undo, redo;
    std::size_t bytes_held = 0;
    for (std::uint32_t k = 0; k < n_undo + n_redo; ++k) {
        Step s;
        s.bytes = sizeof(Step);  // as end_stroke and swap_in count a step
        s.serial = in.u64("a step's serial");
        if (s.serial == 0 || s.serial > serial) throw Error("undo history bytes: a step's serial is out of range");
        for (Vec3* v : {&s.box_m.lo, &s.box_m.hi})
            for (int a = 0; a < 3; ++a) (*v)[a] = in.f64("a step's box");
        const std::uint32_t rays = in.u32("a step's ray count");
        for (std::uint32_t i = 0; i < rays; ++i) {
            RayImage r;
            r.axis = in.u8("a ray's axis");
            r.index = in.u32("a ray's index");
            if (r.axis > 2 || r.index >= copied_[r.axis].size())
                throw Error("undo history bytes: a ray outside this model's lattice");
            const std::uint32_t n = in.u32("a ray's interval count"), capacity = in.u32("a ray's capacity");
            // A capacity is kept exactly (it is what the budget counts), but never more than the bytes could describe.
            if (n > capacity || capacity > (bytes.size() / 10) + 64)
                throw Error("undo history bytes: a ray holds more intervals than its capacity, or an absurd capacity");
            r.intervals.reserve(capacity);
            for (std::uint32_t j = 0; j < n; ++j) {
                Interval iv;
                iv.enter = in.f32("an interval");
                iv.exit = in.f32("an interval");
                iv.enter_material = in.u8("an interval");
                iv.exit_material = in.u8("an interval");
                r.intervals.push_back(iv);
            }
            s.bytes += image_bytes(r);
            s.rays.push_back(std::move(r));
        }
        bytes_held += s.bytes;
        (k < n_undo ? undo : redo).push_back(std::move(s));
    }
    if (!in.done()) throw Error("undo history bytes: bytes after the last step");
    undo_ = std::move(undo);
    redo_ = std::move(redo);
    serial_ = serial;
    counts_ = counts;
    counts_.budget_bytes = budget_;
    bytes_ = bytes_held;
    if (bytes_ > budget_) trim(0);
}

}  // namespace tridex::compute
