// app/session/cluster/frame_message.cpp - encoding and checked decoding of the cluster's messages.
#include "app/session/cluster/frame_message.hpp"

#include <cmath>
#include <cstring>
#include <iterator>

#include "compute/journal/journal_format.hpp"
#include "core/error.hpp"
#include "app/session/wire/message_io.hpp"
#include "app/session/wire/presence_wire.hpp"
#include "core/le_bytes.hpp"
#include "core/tool_sample.hpp"
#include "core/math.hpp"

namespace tridex::app {

namespace {

constexpr unsigned char kMagic[4] = {'T', 'D', 'X', 'C'};
constexpr std::size_t kMaxMenuDepth = 8;                // rings of rings in the menu, at most

// The cluster's messages: the magic, then ClusterKind.
class Writer : public MessageWriter {
public:
    explicit Writer(ClusterKind kind) : MessageWriter(kMagic, static_cast<std::uint8_t>(kind)) {}
};

class Reader : public MessageReader {
public:
    Reader(std::span<const unsigned char> b, const std::string& from, ClusterKind want)
        : MessageReader(b, from, kMagic, static_cast<std::uint8_t>(want), "cluster") {}
};

}  // namespace

std::vector<unsigned char> encode_hello(const HelloMessage& m) {
    Writer w(ClusterKind::kHello);
    w.text(m.spec_json);
    w.u64(m.initial_digest);
    w.blob(m.model_tdx);
    write_late_start(w, m.first_record, m.history, m.prevs, m.last_closed_serial);
    return w.take();
}

HelloMessage decode_hello(std::span<const unsigned char> bytes, const std::string& from) {
    Reader r(bytes, from, ClusterKind::kHello);
    HelloMessage m;
    m.spec_json = r.text("spec");
    m.initial_digest = r.u64("initial_digest");
    m.model_tdx = r.blob("model_tdx");
    read_late_start(r, {&m.first_record, &m.history, &m.prevs, &m.last_closed_serial});
    if (m.first_record > 0 && m.model_tdx.empty()) r.fail("model_tdx", "a late start without the model it starts from");
    r.end();
    return m;
}

std::vector<unsigned char> encode_frame(const FrameMessage& m) {
    Writer w(ClusterKind::kFrame);
    w.u64(m.frame);
    const bool posed = !m.workpiece_pose.is_identity();
    w.u8(static_cast<std::uint8_t>((m.last ? 1 : 0) | (m.show_tool ? 2 : 0) | (m.check_digest ? 4 : 0) |
                                   (m.menu.shown ? 8 : 0) | (posed ? 16 : 0)));
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
    w.records(m.records);
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
    const std::size_t others = std::min<std::size_t>(m.others.size(), kMaxSites);  // a shared session's other sites
    w.u8(static_cast<std::uint8_t>(others));
    for (std::size_t i = 0; i < others; ++i) write_presence(w, m.others[i]);
    if (posed) w.pose(m.workpiece_pose);
    return w.take();
}

FrameMessage decode_frame(std::span<const unsigned char> bytes, const std::string& from) {
    Reader r(bytes, from, ClusterKind::kFrame);
    FrameMessage m;
    m.frame = r.u64("frame");
    const std::uint8_t flags = r.u8("flags");
    if (flags & ~31u) r.fail("flags", "unknown flag bits");
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
    m.records = r.records("records");
    if (m.check_digest && m.check_after > m.records.size()) r.fail("check_after", "past the records");
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
    const std::uint8_t others = r.u8("others");
    if (others > kMaxSites) r.fail("others", std::to_string(others) + " sites, more than a session has");
    for (std::uint8_t i = 0; i < others; ++i) m.others.push_back(read_presence(r));
    if (flags & 16) {
        m.workpiece_pose = r.pose("workpiece_pose");
        if (!is_rigid(m.workpiece_pose))
            r.fail("workpiece_pose", "not a finite rigid pose");
        m.workpiece_pose.orientation = glm::normalize(m.workpiece_pose.orientation);
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

std::vector<unsigned char> encode_let_go(const std::string& why) {
    Writer w(ClusterKind::kLetGo);
    w.text(why);
    return w.take();
}

std::optional<std::string> let_go_reason(std::span<const unsigned char> bytes) {
    if (bytes.size() < 5 || std::memcmp(bytes.data(), kMagic, 4) != 0 || bytes[4] != static_cast<unsigned char>(ClusterKind::kLetGo))
        return std::nullopt;
    try {
        Reader r(bytes, "rank 0", ClusterKind::kLetGo);
        std::string why = r.text("why");
        r.end();
        return why;
    } catch (const Error&) {
        return std::string("(its reason could not be read)");
    }
}

std::size_t frame_message_bytes(std::size_t batches, std::size_t samples, std::size_t marks) {
    constexpr std::size_t kHead = 5 + 8 + 1 + 2 * 56 + 8 + 8 + 24 + 32 + 1 + 8 + 8 + 8 + 8 + 8 + 8 + 4 + 4 + 1;
    return kHead + batches * (1 + 8 + 4) + samples * compute::kJournalSampleBytes + marks * (1 + 8 + 8 + 8);
}

}  // namespace tridex::app
