// app/session/shared/shared_message.hpp - the messages of a shared session between its host and its joiners, on the
// wire: magic "TDXS", a kind byte, then the fields (app/session/wire/message_io.hpp). docs/shared.md gives the
// protocol.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "compute/journal/journal_reader.hpp"
#include "app/session/runtime/site_presence.hpp"
#include "compute/runtime/site_intake.hpp"
#include "core/pose.hpp"
#include "core/tool_sample.hpp"

namespace tridex::app {

/// The protocol version a joiner states in its join; the host refuses another.
inline constexpr std::uint32_t kSharedProtocol = 4;

/// Message kinds (the byte after the magic).
enum class SharedKind : std::uint8_t {
    kJoin = 1,      ///< joiner -> host, once: who joins
    kWelcome = 2,   ///< host -> joiner, once: its site and the session (spec, starting model, digest)
    kSamples = 3,   ///< joiner -> host: its tool's samples, in order
    kRequest = 4,   ///< joiner -> host: an undo, redo or stroke close
    kRecords = 5,   ///< host -> joiner: the stream's records in order, with a digest check now and then
    kRefused = 6,   ///< host -> joiner: a request refused, naming whose stroke stands in the way
    kPresence = 7,  ///< either way, unreliable: a site's tool, for the others to draw
    kEnd = 8,       ///< host -> joiner: the session ended (final digest, records sent) or the joiner was turned away
    kRecordsPacked = 9,  ///< host -> joiner: a kRecords message packed as one zstd frame (a backlog, a burst)
};

/// Records messages at least this long are sent packed (kRecordsPacked) when that is smaller, bytes.
inline constexpr std::size_t kPackRecordsFromBytes = 4096;

/// A joiner's first message.
struct JoinMessage {
    std::uint32_t protocol = kSharedProtocol;
    std::string name;        ///< the person, for the others' screens and messages (1..64 bytes)
    Vec3 colour{0.9, 0.5, 0.1};  ///< their tool's colour, sRGB 0..1
    /// The joiner wants the model the session started with and the whole stream since (its replica's copies, a cluster
    /// wall's render ranks, replay from the start), not the model as it stands.
    bool from_start = false;
};

/// The host's answer to a join.
struct WelcomeMessage {
    std::uint8_t site = 0;                 ///< the joiner's site, 1..kMaxSites-1
    std::string host_name;                 ///< the host's person
    std::string spec_json;                 ///< the session spec (spec_to_json), as the journal's header carries it
    std::vector<unsigned char> model_tdx;  ///< the model the stream starts from, as a .tdx file (zstd sections)
    std::uint64_t initial_digest = 0;      ///< compute::model_digest of that model
    /// The index of the first record the joiner receives: 0 for the session's starting model; for the model as it
    /// stands (a late join), the records before it are in the model.
    std::uint64_t first_record = 0;
    /// A late join: the undo history's steps (SculptSnapshot::history; sent packed with zstd), each site's last
    /// sample, and the newest stroke closed, so that the joiner follows undos of strokes made before it joined.
    std::vector<unsigned char> history{};
    std::vector<ToolSample> prevs{};
    std::uint64_t last_closed_serial = 0;
};

/// The host's stream, continuing: records with indices continuing from the previous message's, and optionally the
/// digest of the host's model after the first check_after of them.
struct RecordsMessage {
    std::vector<compute::JournalRecord> records;
    std::optional<std::uint64_t> check_digest;
    std::uint32_t check_after = 0;
};

/// A refused request (app::SculptRefusal, with the name of who stands in the way).
struct RefusedMessage {
    SculptRequest request = SculptRequest::kUndo;
    std::uint8_t by_site = 0;
    std::string by_name;
};

/// Where a site's tool (and tracked head) is, for the others to draw it (sent unreliably, newest wins).
using PresenceMessage = SitePresence;

/// The end of the host's session (or a join turned away: reason says why, digest 0).
struct EndMessage {
    std::uint64_t digest = 0;   ///< compute::model_digest of the host's final model
    std::uint64_t records = 0;  ///< records the host sent in all
    std::string reason;
};

/// The kind of a shared-session message; throws tridex::Error "<from>: ..." when it is not one.
SharedKind shared_kind(std::span<const unsigned char> bytes, const std::string& from);

/// Encoders and checked decoders; decode_* throw tridex::Error "<from>: <field>: <what>" on a truncated, oversized or
/// malformed message (another kind, a bad magic, a count past the end, a sample no writer writes, a bad site or name).
std::vector<unsigned char> encode_join(const JoinMessage& m);
JoinMessage decode_join(std::span<const unsigned char> b, const std::string& from);
std::vector<unsigned char> encode_welcome(const WelcomeMessage& m);
WelcomeMessage decode_welcome(std::span<const unsigned char> b, const std::string& from);
std::vector<unsigned char> encode_samples(std::span<const ToolSample> samples);
std::vector<ToolSample> decode_samples(std::span<const unsigned char> b, const std::string& from);
std::vector<unsigned char> encode_request(SculptRequest r);
SculptRequest decode_request(std::span<const unsigned char> b, const std::string& from);
/// encode_records packs a message of kPackRecordsFromBytes or more (kRecordsPacked) when that is smaller;
/// decode_records reads either kind.
std::vector<unsigned char> encode_records(const RecordsMessage& m);
RecordsMessage decode_records(std::span<const unsigned char> b, const std::string& from);
std::vector<unsigned char> encode_refused(const RefusedMessage& m);
RefusedMessage decode_refused(std::span<const unsigned char> b, const std::string& from);
std::vector<unsigned char> encode_presence(const PresenceMessage& m);
PresenceMessage decode_presence(std::span<const unsigned char> b, const std::string& from);
std::vector<unsigned char> encode_end(const EndMessage& m);
EndMessage decode_end(std::span<const unsigned char> b, const std::string& from);

}  // namespace tridex::app
