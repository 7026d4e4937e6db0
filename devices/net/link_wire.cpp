// devices/net/link_wire.cpp - encoding and checked decoding of the link datagrams.
#include "devices/net/link_wire.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/le_bytes.hpp"
#include "devices/net/wire_io.hpp"

namespace tridex::devices::net {

const char* to_string(RenderingMode mode) { return mode == RenderingMode::kLocal ? "local" : "distributed"; }

RenderingMode rendering_mode_from(const std::string& name) {
    if (name == "distributed") return RenderingMode::kDistributed;
    if (name == "local") return RenderingMode::kLocal;
    throw Error("--haptic-rendering: '" + name + "' is not distributed or local");
}

const char* to_string(DropReason r) {
    switch (r) {
        case DropReason::kNone: return "none";
        case DropReason::kTooShort: return "shorter than a header";
        case DropReason::kBadMagic: return "bad magic (not a tridex link datagram)";
        case DropReason::kVersion: return "another link version";
        case DropReason::kUnknownType: return "unknown message type";
        case DropReason::kBadLength: return "payload length wrong for its type";
        case DropReason::kNonFinite: return "non-finite number";
        case DropReason::kOutOfRange: return "field out of range";
        case DropReason::kUnexpected: return "message not expected in this mode or state";
        case DropReason::kCount: break;
    }
    return "?";
}

std::uint64_t DropCounts::total() const {
    std::uint64_t t = 0;
    for (std::uint64_t c : by_reason) t += c;
    return t;
}

std::string DropCounts::summary() const {
    std::string s;
    for (int i = 1; i < static_cast<int>(DropReason::kCount); ++i) {
        if (by_reason[i] == 0) continue;
        if (!s.empty()) s += ", ";
        s += to_string(static_cast<DropReason>(i));
        s += ": " + std::to_string(by_reason[i]);
    }
    return s.empty() ? "none" : s;
}

void encode_header(const Header& h, std::vector<std::uint8_t>& out) {
    out.clear();
    Writer w(out);
    w.u32(kLinkMagic);
    w.u16(h.version);
    w.u8(static_cast<std::uint8_t>(h.type));
    w.u8(0);
    w.u32(h.seq);
    w.u64(h.sent_us);
    w.u64(h.echo_us);
}

namespace {

void begin(Header& h, MsgType t, std::vector<std::uint8_t>& out) {
    h.type = t;
    encode_header(h, out);
}

void put_state(Writer& w, const DeviceState& s) {
    w.f64(s.t_s);
    w.vec3(s.pose.position);
    w.quat(s.pose.orientation);
    w.vec3(s.velocity_m_s);
    w.u32(s.buttons);
}

void get_state(Reader& r, DeviceState& s) {
    s.t_s = r.f64();
    s.pose.position = r.vec3();
    s.pose.orientation = r.quat();
    s.velocity_m_s = r.vec3();
    s.buttons = r.u32();
}

// Reader over the payload of a datagram whose header was read; the result kBadLength unless exactly consumed.
DropReason finish(const Reader& r) {
    if (r.failed() || !r.at_end()) return DropReason::kBadLength;
    return r.non_finite() ? DropReason::kNonFinite : DropReason::kNone;
}

}  // namespace

void encode(Header h, const Hello& m, std::vector<std::uint8_t>& out) {
    begin(h, MsgType::kHello, out);
    Writer w(out);
    w.u8(static_cast<std::uint8_t>(m.mode));
    w.u32(m.period_us);
}

void encode(Header h, const Welcome& m, std::vector<std::uint8_t>& out) {
    begin(h, MsgType::kWelcome, out);
    Writer w(out);
    w.str(m.name.substr(0, 200));
    w.vec3(m.workspace_min_m);
    w.vec3(m.workspace_max_m);
    w.f64(m.max_force_n);
    w.f64(m.max_torque_nm);
    w.f64(m.max_stiffness_n_per_m);
    w.u8(m.dof_in);
    w.u8(m.dof_out);
}

void encode_refuse(Header h, const std::string& reason, std::vector<std::uint8_t>& out) {
    begin(h, MsgType::kRefuse, out);
    Writer w(out);
    w.str(reason.substr(0, 400));
}

void encode(Header h, const StateMsg& m, std::vector<std::uint8_t>& out) {
    begin(h, MsgType::kState, out);
    Writer w(out);
    put_state(w, m.state);
    w.vec3(m.applied_force_n);
    w.u8(static_cast<std::uint8_t>((m.watchdog_zeroed ? 1 : 0) | (m.has_tool ? 2 : 0) |
                                   (m.has_tool && m.tool.contact ? 4 : 0) | (m.has_tool && m.tool.hold ? 8 : 0)));
    if (m.has_tool) {
        w.vec3(m.tool.tool_world.position);
        w.quat(m.tool.tool_world.orientation);
        w.vec3(m.tool.proxy_m);
        w.vec3(m.tool.force_n);
    }
    w.u32(m.lost);
    w.u32(m.malformed);
    w.u32(m.stale_snapshots);
    w.u32(m.watchdog_trips);
}

void encode(Header h, const ForceMsg& m, std::vector<std::uint8_t>& out) {
    begin(h, MsgType::kForce, out);
    Writer w(out);
    w.vec3(m.force_n);
    w.vec3(m.torque_nm);
}

void encode(Header h, const ContactMsg& m, std::vector<std::uint8_t>& out) {
    begin(h, MsgType::kContact, out);
    Writer w(out);
    w.f64(m.stiffness_n_per_m);
    w.f64(m.damping_n_s_per_m);
    w.f64(m.tool_radius_m);
    w.f64(m.static_friction);
    w.f64(m.dynamic_friction);
    w.f64(m.ewma_alpha);
    w.vec3(m.device_to_world.position);
    w.quat(m.device_to_world.orientation);
    w.f64(m.workspace_scale);
    w.u8(m.workspace_mode);
    w.u32(m.button_mask);
    for (double v : {m.jump_gain, m.drag_gain, m.bubble_radius_m, m.bubble_rate_m_s, m.bubble_rate_exponent,
                     m.bubble_stiffness_n_per_m})
        w.f64(v);
    w.u32(m.revision);
    const int n = std::clamp<int>(m.point_count, 0, kMaxContactPoints);
    w.u8(static_cast<std::uint8_t>(n));
    w.f64(m.point_radius_m);
    for (int i = 0; i < n; ++i) {
        w.vec3(m.point_local_m[static_cast<std::size_t>(i)]);
        w.vec3(m.point_normal[static_cast<std::size_t>(i)]);
    }
}

void encode_heartbeat(Header h, std::vector<std::uint8_t>& out) { begin(h, MsgType::kHeartbeat, out); }

DropReason decode_header(const std::uint8_t* p, std::size_t n, Header& h, std::uint16_t expected) {
    if (n < kHeaderBytes) return DropReason::kTooShort;
    if (get_u32(p) != kLinkMagic) return DropReason::kBadMagic;
    h.version = static_cast<std::uint16_t>(p[4] | (p[5] << 8));
    h.type = static_cast<MsgType>(p[6]);
    h.seq = get_u32(p + 8);
    h.sent_us = get_u64(p + 12);
    h.echo_us = get_u64(p + 20);
    if (h.version != expected) return DropReason::kVersion;
    if (p[6] < static_cast<std::uint8_t>(MsgType::kHello) || p[6] > static_cast<std::uint8_t>(MsgType::kHeartbeat))
        return DropReason::kUnknownType;
    return DropReason::kNone;
}

DropReason decode(const std::uint8_t* p, std::size_t n, Hello& m) {
    Reader r(p + kHeaderBytes, n - kHeaderBytes);
    const std::uint8_t mode = r.u8();
    m.period_us = r.u32();
    if (const DropReason d = finish(r); d != DropReason::kNone) return d;
    if (mode > 1 || m.period_us < 10 || m.period_us > 100000) return DropReason::kOutOfRange;
    m.mode = static_cast<RenderingMode>(mode);
    return DropReason::kNone;
}

DropReason decode(const std::uint8_t* p, std::size_t n, Welcome& m) {
    Reader r(p + kHeaderBytes, n - kHeaderBytes);
    m.name = r.str(200);
    m.workspace_min_m = r.vec3();
    m.workspace_max_m = r.vec3();
    m.max_force_n = r.f64();
    m.max_torque_nm = r.f64();
    m.max_stiffness_n_per_m = r.f64();
    m.dof_in = r.u8();
    m.dof_out = r.u8();
    if (const DropReason d = finish(r); d != DropReason::kNone) return d;
    if (m.max_force_n < 0.0 || m.max_torque_nm < 0.0 || m.dof_in > 6 || m.dof_out > 6) return DropReason::kOutOfRange;
    return DropReason::kNone;
}

DropReason decode_refuse(const std::uint8_t* p, std::size_t n, std::string& reason) {
    Reader r(p + kHeaderBytes, n - kHeaderBytes);
    reason = r.str(400);
    return finish(r);
}

DropReason decode(const std::uint8_t* p, std::size_t n, StateMsg& m) {
    Reader r(p + kHeaderBytes, n - kHeaderBytes);
    get_state(r, m.state);
    m.applied_force_n = r.vec3();
    const std::uint8_t flags = r.u8();
    m.watchdog_zeroed = (flags & 1) != 0;
    m.has_tool = (flags & 2) != 0;
    m.tool = ToolPart{};
    if (m.has_tool) {
        m.tool.tool_world.position = r.vec3();
        m.tool.tool_world.orientation = r.quat();
        m.tool.proxy_m = r.vec3();
        m.tool.force_n = r.vec3();
        m.tool.contact = (flags & 4) != 0;
        m.tool.hold = (flags & 8) != 0;
    }
    m.lost = r.u32();
    m.malformed = r.u32();
    m.stale_snapshots = r.u32();
    m.watchdog_trips = r.u32();
    if (const DropReason d = finish(r); d != DropReason::kNone) return d;
    if (flags > 15 || (!m.has_tool && (flags & 12) != 0)) return DropReason::kOutOfRange;
    if (m.has_tool) {
        const Quat& q = m.tool.tool_world.orientation;
        if (std::abs(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z - 1.0) > 1e-3) return DropReason::kOutOfRange;
    }
    return DropReason::kNone;
}

DropReason decode(const std::uint8_t* p, std::size_t n, ForceMsg& m) {
    Reader r(p + kHeaderBytes, n - kHeaderBytes);
    m.force_n = r.vec3();
    m.torque_nm = r.vec3();
    return finish(r);
}

DropReason decode(const std::uint8_t* p, std::size_t n, ContactMsg& m) {
    Reader r(p + kHeaderBytes, n - kHeaderBytes);
    m.stiffness_n_per_m = r.f64();
    m.damping_n_s_per_m = r.f64();
    m.tool_radius_m = r.f64();
    m.static_friction = r.f64();
    m.dynamic_friction = r.f64();
    m.ewma_alpha = r.f64();
    m.device_to_world.position = r.vec3();
    m.device_to_world.orientation = r.quat();
    m.workspace_scale = r.f64();
    m.workspace_mode = r.u8();
    m.button_mask = r.u32();
    for (double* v : {&m.jump_gain, &m.drag_gain, &m.bubble_radius_m, &m.bubble_rate_m_s, &m.bubble_rate_exponent,
                      &m.bubble_stiffness_n_per_m})
        *v = r.f64();
    m.revision = r.u32();
    m.point_count = r.u8();
    m.point_radius_m = r.f64();
    if (r.failed()) return DropReason::kBadLength;
    if (m.point_count > kMaxContactPoints) return DropReason::kOutOfRange;
    for (int i = 0; i < m.point_count; ++i) {
        m.point_local_m[static_cast<std::size_t>(i)] = r.vec3();
        m.point_normal[static_cast<std::size_t>(i)] = r.vec3();
    }
    if (const DropReason d = finish(r); d != DropReason::kNone) return d;
    if (m.stiffness_n_per_m < 0.0 || m.damping_n_s_per_m < 0.0 || m.tool_radius_m < 0.0 || m.static_friction < 0.0 ||
        m.dynamic_friction < 0.0 || m.ewma_alpha < 0.0 || m.ewma_alpha >= 1.0 || !(m.workspace_scale > 0.0) ||
        m.point_radius_m < 0.0)
        return DropReason::kOutOfRange;
    return DropReason::kNone;
}

DeviceProfile profile_from(const Welcome& w) {
    DeviceProfile p;
    p.name = w.name;
    p.workspace_m = Aabb{w.workspace_min_m, w.workspace_max_m};
    p.max_force_n = w.max_force_n;
    p.max_torque_nm = w.max_torque_nm;
    p.max_stiffness_n_per_m = w.max_stiffness_n_per_m;
    p.dof_in = w.dof_in;
    p.dof_out = w.dof_out;
    return p;
}

Welcome welcome_from(const DeviceProfile& p) {
    Welcome w;
    w.name = p.name;
    w.workspace_min_m = p.workspace_m.lo;
    w.workspace_max_m = p.workspace_m.hi;
    w.max_force_n = p.max_force_n;
    w.max_torque_nm = p.max_torque_nm;
    w.max_stiffness_n_per_m = p.max_stiffness_n_per_m;
    w.dof_in = static_cast<std::uint8_t>(p.dof_in);
    w.dof_out = static_cast<std::uint8_t>(p.dof_out);
    return w;
}

}  // namespace tridex::devices::net
