// app/session/cluster/frame_message.hpp - the messages of a cluster session on the wire: rank 0's hello and frame
// messages to the render ranks, and their answers. Little-endian, doubles bit for bit (core/le_bytes.hpp).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "app/menu/menu_frame.hpp"
#include "app/session/runtime/site_presence.hpp"
#include "compute/journal/journal_reader.hpp"
#include "core/pose.hpp"
#include "core/tool_sample.hpp"
#include "core/tool_shape.hpp"

namespace tridex::app {

/// Message kinds (the first byte after the 4-byte magic "TDXC").
enum class ClusterKind : std::uint8_t {
    kHello = 1,   ///< rank 0 -> render ranks, once: the session
    kFrame = 2,   ///< rank 0 -> render ranks, once a frame
    kReady = 3,   ///< render rank -> rank 0: frame applied and drawn, ready to present
    kGo = 4,      ///< rank 0 -> render ranks: present the frame (the swap barrier's release)
    kDone = 5,    ///< render rank -> rank 0: the last frame presented, outputs written; its report
    kLetGo = 6,   ///< rank 0 -> a render rank it lets go (a network wall): why; the rank ends
};

/// RankAnswer::frame of the answer to the hello: the workpiece is built and checked, the viewports are open.
inline constexpr std::uint64_t kHelloAnswerFrame = ~std::uint64_t{0};

/// The session, sent once before the first frame: what a render rank needs to build the same workpiece.
struct HelloMessage {
    std::string spec_json;          ///< the session spec (spec_to_json), as the journal's header carries it
    std::uint64_t initial_digest = 0;  ///< compute::model_digest of rank 0's workpiece before the first sample
    /// The saved model file (.tdx) the session started from, its bytes as they are, when it started from one (a
    /// shared session's joiner starts from the host's model): a render rank builds its replica from them rather than
    /// from a path that may exist on rank 0's machine only. Empty: the spec's mesh, scan-converted as rank 0 did.
    std::vector<unsigned char> model_tdx;
    /// A render rank that joins a running wall, or takes the place of one that failed (a network wall): model_tdx is
    /// the model as it stood then (a snapshot, SculptThread::ask_snapshot, saved as .tdx), initial_digest its digest,
    /// and the stream goes on from record first_record. With it come the undo history's steps (sent packed with
    /// zstd), each site's last sample (sweeps continue from it) and the newest stroke closed, so that undos of strokes
    /// made before it joined apply here as at rank 0. At the session's start: 0 and empty.
    std::uint64_t first_record = 0;
    std::vector<unsigned char> history{};
    std::vector<ToolSample> prevs{};
    std::uint64_t last_closed_serial = 0;
};

/// The tool sample stream's records since the last frame, plus what the frame shows.
struct FrameMessage {
    std::uint64_t frame = 0;        ///< 0, 1, 2, ...
    bool last = false;              ///< the session ended: this frame is the last (its records are the final ones)
    Pose head;                      ///< the head pose the frame is drawn from, world m
    Pose nav_pose;                  ///< scene navigation: rigid part of world_from_scene
    double nav_scale = 1.0;         ///< and its uniform scale
    double eye_separation_m = 0.0;  ///< m
    bool show_tool = true;          ///< draw the tool
    Vec3 tool_m{0.0};               ///< tool centre, world m
    Quat tool_orientation{1.0, 0.0, 0.0, 0.0};
    ToolShape tool;                 ///< the tool's shape (ball, flat end; a mesh tool is drawn as its bounding ball)
    double ao = 1.0;                ///< ambient occlusion strength, 0..1
    Pose workpiece_pose{};          ///< the workpiece's pose as rank 0 draws it (model -> world; sent when not identity)
    std::vector<compute::JournalRecord> records;  ///< batches and marks in journal order (indices continuing)
    /// A digest check: model_digest of rank 0's model after the first check_after records of `records`.
    std::optional<std::uint64_t> check_digest;
    std::uint32_t check_after = 0;
    double newest_sample_made_s = 0.0;  ///< steady-clock time of the newest sample in `records` (0: none), s
    double sent_s = 0.0;                ///< steady-clock time rank 0 sent the message, s
    MenuFrame menu;                     ///< the pie menu as rank 0 drew it (not shown: none)
    /// The other sites of a shared session rank 0 takes part in (FrameShown::others; at most kMaxSites), drawn by
    /// every render rank as rank 0 draws them (PresenceView).
    std::vector<SitePresence> others{};
};

/// A render rank's answer to a frame (kReady) or to the end (kDone).
struct RankAnswer {
    ClusterKind kind = ClusterKind::kReady;
    std::uint64_t frame = 0;
    /// A digest check failed on this rank: its digest (the message also says so in `error`).
    bool digest_mismatch = false;
    std::uint64_t digest = 0;
    std::string error;              ///< why this rank cannot go on ("" = fine): ends the session
    double previous_present_s = 0.0;  ///< steady-clock time the previous frame was presented (0: none), s
    double apply_ms = 0.0;          ///< time applying this frame's records, ms
    double draw_ms = 0.0;           ///< time contouring the changed tiles and drawing every viewport, ms
    std::string report_json;        ///< kDone: the rank's report (JSON text)
};

/// Encodes each message; decode_* throw tridex::Error "<from>: <field>: <what>" on a truncated, oversized or
/// malformed message (another kind, a bad magic, a count past the end, a sample no writer writes).
std::vector<unsigned char> encode_hello(const HelloMessage& m);
HelloMessage decode_hello(std::span<const unsigned char> bytes, const std::string& from);
std::vector<unsigned char> encode_frame(const FrameMessage& m);
FrameMessage decode_frame(std::span<const unsigned char> bytes, const std::string& from);
std::vector<unsigned char> encode_answer(const RankAnswer& m);
RankAnswer decode_answer(std::span<const unsigned char> bytes, const std::string& from);
std::vector<unsigned char> encode_go(std::uint64_t frame);
std::uint64_t decode_go(std::span<const unsigned char> bytes, const std::string& from);

/// Rank 0's word to a render rank it lets go (ClusterKind::kLetGo), and its reason: the message's `why`, or nullopt
/// when `bytes` are another message (of any kind, or none: the caller decodes them as it expects).
std::vector<unsigned char> encode_let_go(const std::string& why);
std::optional<std::string> let_go_reason(std::span<const unsigned char> bytes);

/// Bytes one frame message takes on the wire for `samples` samples and `marks` marks (sizing, the bench's figures).
std::size_t frame_message_bytes(std::size_t batches, std::size_t samples, std::size_t marks);

}  // namespace tridex::app
