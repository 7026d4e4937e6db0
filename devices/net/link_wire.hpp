// devices/net/link_wire.hpp - the datagrams between a device server and a session: a fixed header (magic,
// version, type, sequence number, time stamps) and one payload per message type, little-endian.
#pragma once

#include <cstddef>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/math.hpp"
#include "devices/haptic_device.hpp"

namespace tridex::devices::net {

/// Version of the datagram layout; a peer with another version is refused at the handshake.
/// 2: kState carries the tool sample of the server's contact loop in local rendering.
/// 3: kContact carries the tool's contact points (the interaction mesh), not only a radius.
inline constexpr std::uint16_t kLinkVersion = 3;
/// First four bytes of every datagram: "TDXL".
inline constexpr std::uint32_t kLinkMagic = 0x4c584454u;
/// Bytes of the header every datagram starts with.
inline constexpr std::size_t kHeaderBytes = 28;
/// Largest datagram accepted (a snapshot fits in well under this), bytes.
inline constexpr std::size_t kMaxDatagramBytes = 1u << 20;

/// Where the 1 kHz contact loop runs (Popescu, Burdea, Bouzit, section 2).
enum class RenderingMode : std::uint8_t {
    kDistributed = 0,  ///< the session computes the force from the state it receives and sends it back
    kLocal = 1,        ///< the server runs the god-object next to the device on snapshots the session sends
};

/// "distributed" or "local".
const char* to_string(RenderingMode mode);
/// Parses "distributed" / "local"; throws tridex::Error "--haptic-rendering: 'x' is not distributed or local".
RenderingMode rendering_mode_from(const std::string& name);

/// Message types (the header's type byte).
enum class MsgType : std::uint8_t {
    kHello = 1,      ///< session -> server: mode and period; answered by kWelcome or kRefuse
    kWelcome = 2,    ///< server -> session: the device's profile
    kRefuse = 3,     ///< either way: one line saying why the peer is refused
    kState = 4,      ///< server -> session: one device sample per server tick, the server's counters and (local) the tool
    kForce = 5,      ///< session -> server (distributed): force and torque to send to the device
    kSurface = 6,    ///< session -> server (local): an ActiveSurface snapshot (devices/net/surface_codec.hpp)
    kContact = 7,    ///< session -> server (local): contact parameters and the workspace mapping
    kHeartbeat = 8,  ///< session -> server (local): keeps the server's watchdog fed between snapshots
};

/// The header of every datagram. Times are microseconds of the sender's monotonic clock.
struct Header {
    std::uint16_t version = kLinkVersion;
    MsgType type = MsgType::kHeartbeat;
    std::uint32_t seq = 0;      ///< per sender and type stream, +1 per datagram (gaps = lost datagrams)
    std::uint64_t sent_us = 0;  ///< sender's clock when sent, us
    std::uint64_t echo_us = 0;  ///< the newest sent_us the sender has received from its peer (0 = none): RTT
};

/// kHello payload.
struct Hello {
    RenderingMode mode = RenderingMode::kDistributed;
    std::uint32_t period_us = 1000;  ///< the session's haptic loop period, us
};

/// kWelcome payload: the served device's profile (the fields the session's loop needs).
struct Welcome {
    std::string name;  ///< profile name, at most 200 bytes
    Vec3 workspace_min_m{0.0}, workspace_max_m{0.0};
    double max_force_n = 0.0, max_torque_nm = 0.0, max_stiffness_n_per_m = 0.0;
    std::uint8_t dof_in = 0, dof_out = 0;
};

/// The tool sample of the server's contact loop (local rendering), world frame, SI: what the session sculpts with.
using ToolPart = RemoteToolSample;

/// kState payload: one device sample (device frame, SI) and the server's counters; in local rendering also the
/// tool sample of the server's contact loop for the same tick (the device state's time and buttons go with it).
struct StateMsg {
    DeviceState state;
    bool has_tool = false;           ///< `tool` is filled (local rendering with contact parameters set)
    ToolPart tool;
    Vec3 applied_force_n{0.0};       ///< force the server sent to the device on this tick, N
    bool watchdog_zeroed = false;    ///< the server's watchdog held the force at zero (silent link)
    std::uint32_t lost = 0;          ///< datagrams from the session the server found missing (sequence gaps)
    std::uint32_t malformed = 0;     ///< datagrams the server dropped as malformed
    std::uint32_t stale_snapshots = 0;  ///< local mode: snapshots that reached the server too old to use
    std::uint32_t watchdog_trips = 0;   ///< times the server's watchdog zeroed the force
};

/// kForce payload (device frame).
struct ForceMsg {
    Vec3 force_n{0.0};
    Vec3 torque_nm{0.0};
};

/// Most contact points a kContact message carries (haptics::kMaxToolPoints).
inline constexpr int kMaxContactPoints = 64;

/// kContact payload: what the server's god-object loop needs from the session (SI units).
struct ContactMsg {
    double stiffness_n_per_m = 700.0;
    double damping_n_s_per_m = 0.5;
    double tool_radius_m = 0.0;
    double static_friction = 0.0;
    double dynamic_friction = 0.0;
    double ewma_alpha = 0.9;
    Pose device_to_world;          ///< device frame -> world
    double workspace_scale = 1.0;  ///< world = R * (s * p) + offset
    /// Workspace moving (haptics::WorkspaceConfig, the same meaning and units): the technique as the value of
    /// haptics::WorkspaceMode (0..255 on the wire; the server's loop refuses one it does not know) and its parameters.
    std::uint8_t workspace_mode = 0;
    std::uint32_t button_mask = 1u;
    double jump_gain = 1.0, drag_gain = 1.0;
    double bubble_radius_m = 0.0, bubble_rate_m_s = 0.5, bubble_rate_exponent = 3.0, bubble_stiffness_n_per_m = 50.0;
    std::uint32_t revision = 0;    ///< +1 whenever the session changes any of these
    /// The tool's contact points (haptics::ToolPoints: tool frame, m): how many, 0..kMaxContactPoints (0 = the
    /// single god-object of tool_radius_m; two = the wand's pair, more = Popescu's haptic interaction mesh), the
    /// ball radius around each (m, >= 0), their positions and outward unit normals (zero when none). Only
    /// `point_count` of each go on the wire.
    std::uint8_t point_count = 0;
    double point_radius_m = 0.0;
    std::array<Vec3, kMaxContactPoints> point_local_m{};
    std::array<Vec3, kMaxContactPoints> point_normal{};
};

/// Appends a header to out (cleared first).
void encode_header(const Header& h, std::vector<std::uint8_t>& out);
/// Encoders: the header (type set by the function) and the payload, into out (cleared first).
void encode(Header h, const Hello& m, std::vector<std::uint8_t>& out);
void encode(Header h, const Welcome& m, std::vector<std::uint8_t>& out);
void encode_refuse(Header h, const std::string& reason, std::vector<std::uint8_t>& out);
void encode(Header h, const StateMsg& m, std::vector<std::uint8_t>& out);
void encode(Header h, const ForceMsg& m, std::vector<std::uint8_t>& out);
void encode(Header h, const ContactMsg& m, std::vector<std::uint8_t>& out);
void encode_heartbeat(Header h, std::vector<std::uint8_t>& out);

/// Why a datagram was dropped.
enum class DropReason : std::uint8_t {
    kNone = 0,
    kTooShort,        ///< fewer bytes than a header
    kBadMagic,        ///< not a tridex link datagram
    kVersion,         ///< another link version (only kHello / kRefuse are read across versions)
    kUnknownType,     ///< a type byte this version does not know
    kBadLength,       ///< payload shorter or longer than its type needs
    kNonFinite,       ///< a NaN or infinite number where a finite one is required
    kOutOfRange,      ///< a field outside its range (e.g. a mode byte, a snapshot window size)
    kUnexpected,      ///< a well-formed message this peer does not take in its state (e.g. kForce in local mode)
    kCount
};
/// A short phrase for the reason ("shorter than a header", ...).
const char* to_string(DropReason r);

/// Reads the header of a datagram; kNone on success. A version other than `expected` gives kVersion but still
/// fills h (so the caller can answer a kHello of another version with a kRefuse, and read a kRefuse, whose
/// layout every version keeps).
DropReason decode_header(const std::uint8_t* p, std::size_t n, Header& h, std::uint16_t expected = kLinkVersion);
/// Payload decoders (p, n: the whole datagram; the header was read by decode_header). kNone on success.
DropReason decode(const std::uint8_t* p, std::size_t n, Hello& m);
DropReason decode(const std::uint8_t* p, std::size_t n, Welcome& m);
DropReason decode_refuse(const std::uint8_t* p, std::size_t n, std::string& reason);
DropReason decode(const std::uint8_t* p, std::size_t n, StateMsg& m);
DropReason decode(const std::uint8_t* p, std::size_t n, ForceMsg& m);
DropReason decode(const std::uint8_t* p, std::size_t n, ContactMsg& m);

/// Counts of dropped datagrams by reason.
struct DropCounts {
    std::uint64_t by_reason[static_cast<int>(DropReason::kCount)] = {};
    /// Adds one drop.
    void add(DropReason r) { ++by_reason[static_cast<int>(r)]; }
    /// All drops.
    std::uint64_t total() const;
    /// "bad magic: 2, version: 1" (reasons with a count only); "none" when empty.
    std::string summary() const;
};

/// A profile from a kWelcome, and the kWelcome of a profile.
DeviceProfile profile_from(const Welcome& w);
Welcome welcome_from(const DeviceProfile& p);

}  // namespace tridex::devices::net
