// app/session/cluster/frame_message.cpp - encoding and checked decoding of the cluster's messages.
#include "app/session/cluster/frame_message.hpp"

#include <cmath>
#include <cstring>
#include <iterator>

#include "compute/journal/journal_format.hpp"
#include "core/error.hpp"
#include "devices/net/wire_io.hpp"
#include "core/le_bytes.hpp"
#include "core/math.hpp"

namespace tridex::app {

namespace {

constexpr unsigned char kMagic[4] = {'T', 'D', 'X', 'C'};
constexpr std::uint32_t kMaxRecords = 1u << 20;      // records in one frame message
constexpr std::uint32_t kMaxSamples = 1u << 22;      // samples in one record
constexpr std::uint32_t kMaxText = 64u << 20;        // a spec, an error, a report
constexpr std::size_t kMaxMenuDepth = 8;                // rings of rings in the menu, at most

// The messages' writer: devices/net's little-endian writer, plus texts with a u32 length, poses and samples.
class Writer {
public:
    explicit Writer(ClusterKind kind) : bytes_(std::begin(kMagic), std::end(kMagic)), w_(bytes_) {
        w_.u8(static_cast<std::uint8_t>(kind));
    }
    void u8(std::uint8_t v) { w_.u8(v); }
    void u32(std::uint32_t v) { w_.u32(v); }
    void u64(std::uint64_t v) { w_.u64(v); }
    void f64(double v) { w_.f64(v); }
    void vec3(const Vec3& v) { w_.vec3(v); }
    void quat(const Quat& q) { w_.quat(q); }
    void pose(const Pose& p) { vec3(p.position), quat(p.orientation); }
    void text(const std::string& s) {
        u32(static_cast<std::uint32_t>(s.size()));
        bytes_.insert(bytes_.end(), s.begin(), s.end());
    }
    void sample(const ToolSample& s) {
        const std::size_t at = bytes_.size();
        bytes_.resize(at + compute::kJournalSampleBytes);
        compute::encode_sample(s, bytes_.data() + at);
    }
    std::vector<unsigned char> take() { return std::move(bytes_); }

private:
    std::vector<unsigned char> bytes_;
    devices::net::Writer w_;
};

// The messages' reader: devices/net's bounds-checked little-endian reader, with each value's field named when it is
// missing or not finite, and texts with a u32 length, poses and samples.
class Reader {
public:
    Reader(std::span<const unsigned char> b, const std::string& from, ClusterKind want)
        : r_(b.data(), b.size()), size_(b.size()), from_(from) {
        const std::uint8_t* magic = r_.bytes(4);
        if (!magic || std::memcmp(magic, kMagic, 4) != 0) fail("magic", "not a tridex cluster message");
        const std::uint8_t kind = u8("kind");
        if (kind != static_cast<std::uint8_t>(want))
            fail("kind", "expected kind " + std::to_string(static_cast<int>(want)) + ", got " + std::to_string(kind));
    }
    [[noreturn]] void fail(const std::string& field, const std::string& what) const {
        throw Error(from_ + ": " + field + ": " + what);
    }
    /// Refuses the message, naming `field`, when fewer than n bytes remain (before reserving room for them).
    void need(std::size_t n, const char* field) const {
        if (r_.remaining() < n) truncated(n, field);
    }
    std::uint8_t u8(const char* field) { return checked(r_.u8(), 1, field); }
    std::uint32_t u32(const char* field) { return checked(r_.u32(), 4, field); }
    std::uint64_t u64(const char* field) { return checked(r_.u64(), 8, field); }
    double f64(const char* field) { return checked(r_.f64(), 8, field); }
    Vec3 vec3(const char* field) {
        const double x = f64(field), y = f64(field), z = f64(field);
        return Vec3(x, y, z);
    }
    Quat quat(const char* field) {
        const double w = f64(field), x = f64(field), y = f64(field), z = f64(field);
        const Quat q(w, x, y, z);
        if (!(glm::length(q) > 0.5)) fail(field, "not a unit quaternion");
        return q;
    }
    Pose pose(const char* field) {
        Pose p;
        p.position = vec3(field);
        p.orientation = quat(field);
        return p;
    }
    std::string text(const char* field) {
        const std::uint32_t n = u32(field);
        if (n > kMaxText) fail(field, "length " + std::to_string(n) + " over the limit");
        const std::uint8_t* p = checked(r_.bytes(n), n, field);
        return std::string(reinterpret_cast<const char*>(p), n);
    }
    ToolSample sample(const char* field) {
        const std::uint8_t* p = checked(r_.bytes(compute::kJournalSampleBytes), compute::kJournalSampleBytes, field);
        ToolSample s;
        if (!compute::decode_sample(p, s)) fail(field, "a sample no writer writes");
        if (!std::isfinite(s.t_s) || !is_finite(s.position) || !std::isfinite(s.tool.radius_m) || s.tool.radius_m < 0.0 ||
            !std::isfinite(s.tool.length_m) || s.tool.length_m < 0.0)
            fail(field, "a sample with a non-finite or negative field");
        return s;
    }
    void end() const {
        if (!r_.at_end()) fail("end", std::to_string(r_.remaining()) + " bytes after the message");
    }

private:
    // `v`, read as `n` bytes of `field`: refused when the message ended before it (the reader's position is then
    // where it stopped) or when it holds a number that is not finite.
    template <class T>
    T checked(T v, std::size_t n, const char* field) {
        if (r_.failed()) truncated(n, field);
        if (r_.non_finite()) fail(field, "not a finite number");
        return v;
    }

    [[noreturn]] void truncated(std::size_t n, const char* field) const {
        fail(field, "truncated message (" + std::to_string(size_) + " bytes, " + std::to_string(n) +
                        " more needed at byte " + std::to_string(size_ - r_.remaining()) + ")");
    }

    devices::net::Reader r_;
    std::size_t size_;
    std::string from_;
};

}  // namespace

std::vector<unsigned char> encode_hello(const HelloMessage& m) {
    Writer w(ClusterKind::kHello);
    w.text(m.spec_json);
    w.u64(m.initial_digest);
    return w.take();
}

HelloMessage decode_hello(std::span<const unsigned char> bytes, const std::string& from) {
    Reader r(bytes, from, ClusterKind::kHello);
    HelloMessage m;
    m.spec_json = r.text("spec");
    m.initial_digest = r.u64("initial_digest");
    r.end();
    return m;
}

std::vector<unsigned char> encode_frame(const FrameMessage& m) {
    Writer w(ClusterKind::kFrame);
    w.u64(m.frame);
    w.u8(static_cast<std::uint8_t>((m.last ? 1 : 0) | (m.show_tool ? 2 : 0) | (m.check_digest ? 4 : 0) |
                                   (m.menu.shown ? 8 : 0)));
    w.pose(m.head);
    w.pose(m.nav_pose);
    w.f64(m.nav_scale);
    w.f64(m.eye_separation_m);
    w.vec3(m.tool_m);
    w.quat(m.tool_orientation);
    w.u8(static_cast<std::uint8_t>(m.tool.kind));
    w.f64(m.tool.radius_m);
    w.f64(m.tool.length_m);
    w.f64(m.ao);
    w.f64(m.newest_sample_made_s);
    w.f64(m.sent_s);
    w.u64(m.check_digest.value_or(0));
    w.u32(m.check_after);
    w.u32(static_cast<std::uint32_t>(m.records.size()));
    for (const compute::JournalRecord& rec : m.records) {
        w.u8(static_cast<std::uint8_t>(rec.kind));
        w.u64(rec.index);
        if (rec.kind == compute::JournalKind::kBatch) {
            w.u32(static_cast<std::uint32_t>(rec.samples.size()));
            for (const ToolSample& s : rec.samples) w.sample(s);
        } else {
            w.u64(rec.serial);
            w.u64(rec.rays);
        }
    }
    if (m.menu.shown) {  // the pie menu as rank 0 drew it
        const MenuFrame& f = m.menu;
        for (const Vec3& v : {f.centre_m, f.right, f.up, f.normal}) w.vec3(v);
        w.f64(f.radius_m);
        w.f64(f.dead_radius_m);
        w.u8(static_cast<std::uint8_t>(std::min<std::size_t>(f.path.size(), kMaxMenuDepth)));
        for (std::size_t i = 0; i < f.path.size() && i < kMaxMenuDepth; ++i) w.u8(f.path[i]);
        w.u8(static_cast<std::uint8_t>(f.highlighted + 1));
        w.text(f.status);
    }
    return w.take();
}

FrameMessage decode_frame(std::span<const unsigned char> bytes, const std::string& from) {
    Reader r(bytes, from, ClusterKind::kFrame);
    FrameMessage m;
    m.frame = r.u64("frame");
    const std::uint8_t flags = r.u8("flags");
    if (flags & ~15u) r.fail("flags", "unknown flag bits");
    m.last = flags & 1;
    m.show_tool = flags & 2;
    m.head = r.pose("head");
    m.nav_pose = r.pose("nav_pose");
    m.nav_scale = r.f64("nav_scale");
    if (!(m.nav_scale > 0.0)) r.fail("nav_scale", "must be > 0");
    m.eye_separation_m = r.f64("eye_separation_m");
    if (m.eye_separation_m < 0.0 || m.eye_separation_m > 0.2) r.fail("eye_separation_m", "must be in [0, 0.2] m");
    m.tool_m = r.vec3("tool_m");
    m.tool_orientation = r.quat("tool_orientation");
    const std::uint8_t kind = r.u8("tool.kind");
    if (kind > static_cast<std::uint8_t>(ToolKind::kMesh)) r.fail("tool.kind", "unknown tool kind");
    m.tool.kind = static_cast<ToolKind>(kind);
    m.tool.radius_m = r.f64("tool.radius_m");
    m.tool.length_m = r.f64("tool.length_m");
    if (m.tool.radius_m < 0.0 || m.tool.length_m < 0.0) r.fail("tool", "negative size");
    m.ao = r.f64("ao");
    if (m.ao < 0.0 || m.ao > 1.0) r.fail("ao", "must be in [0, 1]");
    m.newest_sample_made_s = r.f64("newest_sample_made_s");
    m.sent_s = r.f64("sent_s");
    const std::uint64_t digest = r.u64("check_digest");
    m.check_after = r.u32("check_after");
    if (flags & 4) m.check_digest = digest;
    const std::uint32_t n = r.u32("records");
    if (n > kMaxRecords) r.fail("records", std::to_string(n) + " records, over the limit");
    if (m.check_digest && m.check_after > n) r.fail("check_after", "past the records");
    m.records.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i) {
        compute::JournalRecord rec;
        const std::uint8_t k = r.u8("record.kind");
        if (k < 1 || k > 4) r.fail("record.kind", "record " + std::to_string(i) + ": unknown kind " + std::to_string(k));
        rec.kind = static_cast<compute::JournalKind>(k);
        rec.index = r.u64("record.index");
        if (rec.kind == compute::JournalKind::kBatch) {
            const std::uint32_t ns = r.u32("record.samples");
            if (ns > kMaxSamples) r.fail("record.samples", std::to_string(ns) + " samples, over the limit");
            r.need(static_cast<std::size_t>(ns) * compute::kJournalSampleBytes, "record.samples");
            rec.samples.reserve(ns);
            for (std::uint32_t s = 0; s < ns; ++s) rec.samples.push_back(r.sample("record.sample"));
        } else {
            rec.serial = r.u64("record.serial");
            rec.rays = r.u64("record.rays");
        }
        m.records.push_back(std::move(rec));
    }
    if (flags & 8) {
        MenuFrame& f = m.menu;
        f.shown = true;
        f.centre_m = r.vec3("menu.centre_m");
        f.right = r.vec3("menu.right");
        f.up = r.vec3("menu.up");
        f.normal = r.vec3("menu.normal");
        f.radius_m = r.f64("menu.radius_m");
        f.dead_radius_m = r.f64("menu.dead_radius_m");
        if (!(f.radius_m > 0.0 && f.dead_radius_m > 0.0 && f.dead_radius_m < f.radius_m))
            r.fail("menu.radius_m", "radii must be 0 < dead < radius");
        const std::uint8_t depth = r.u8("menu.path");
        if (depth > kMaxMenuDepth) r.fail("menu.path", "deeper than the menu");
        for (std::uint8_t i = 0; i < depth; ++i) f.path.push_back(r.u8("menu.path"));
        f.highlighted = static_cast<int>(r.u8("menu.highlighted")) - 1;
        f.status = r.text("menu.status");
    }
    r.end();
    return m;
}

std::vector<unsigned char> encode_answer(const RankAnswer& m) {
    Writer w(m.kind);
    w.u64(m.frame);
    w.u8(m.digest_mismatch ? 1 : 0);
    w.u64(m.digest);
    w.text(m.error);
    w.f64(m.previous_present_s);
    w.f64(m.apply_ms);
    w.f64(m.draw_ms);
    w.text(m.report_json);
    return w.take();
}

RankAnswer decode_answer(std::span<const unsigned char> bytes, const std::string& from) {
    const ClusterKind kind = bytes.size() > 4 && bytes[4] == static_cast<unsigned char>(ClusterKind::kDone) ? ClusterKind::kDone
                                                                                                       : ClusterKind::kReady;
    Reader r(bytes, from, kind);
    RankAnswer m;
    m.kind = kind;
    m.frame = r.u64("frame");
    m.digest_mismatch = r.u8("digest_mismatch") != 0;
    m.digest = r.u64("digest");
    m.error = r.text("error");
    m.previous_present_s = r.f64("previous_present_s");
    m.apply_ms = r.f64("apply_ms");
    m.draw_ms = r.f64("draw_ms");
    m.report_json = r.text("report");
    r.end();
    return m;
}

std::vector<unsigned char> encode_go(std::uint64_t frame) {
    Writer w(ClusterKind::kGo);
    w.u64(frame);
    return w.take();
}

std::uint64_t decode_go(std::span<const unsigned char> bytes, const std::string& from) {
    Reader r(bytes, from, ClusterKind::kGo);
    const std::uint64_t f = r.u64("frame");
    r.end();
    return f;
}

std::size_t frame_message_bytes(std::size_t batches, std::size_t samples, std::size_t marks) {
    constexpr std::size_t kHead = 5 + 8 + 1 + 2 * 56 + 8 + 8 + 24 + 32 + 1 + 8 + 8 + 8 + 8 + 8 + 8 + 4 + 4;
    return kHead + batches * (1 + 8 + 4) + samples * compute::kJournalSampleBytes + marks * (1 + 8 + 8 + 8);
}

}  // namespace tridex::app
