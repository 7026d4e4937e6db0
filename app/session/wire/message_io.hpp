// app/session/wire/message_io.hpp - the writer and checked reader of tridex's session messages between machines (a
// cluster's ranks, a shared session's sites): a 4-byte magic, a kind byte, then little-endian fields, doubles bit for
// bit, texts with a u32 length, poses, tool samples (the journal's encoding) and journal records.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "compute/journal/journal_reader.hpp"
#include "core/pose.hpp"
#include "core/tool_sample.hpp"
#include "devices/net/wire_io.hpp"

namespace tridex::app {

/// Longest text (a spec, an error, a report) and blob (a model file) a reader accepts, bytes.
inline constexpr std::uint32_t kMaxMessageText = 64u << 20;
inline constexpr std::uint32_t kMaxMessageBlob = 1u << 30;
/// Most records in one message and samples in one record a reader accepts.
inline constexpr std::uint32_t kMaxMessageRecords = 1u << 20;
inline constexpr std::uint32_t kMaxRecordSamples = 1u << 22;

/// Builds one message: the magic, the kind byte, then the fields in the order written.
class MessageWriter {
public:
    MessageWriter(const unsigned char (&magic)[4], std::uint8_t kind);
    void u8(std::uint8_t v) { w_.u8(v); }
    void u32(std::uint32_t v) { w_.u32(v); }
    void u64(std::uint64_t v) { w_.u64(v); }
    void f64(double v) { w_.f64(v); }
    void vec3(const Vec3& v) { w_.vec3(v); }
    void quat(const Quat& q) { w_.quat(q); }
    void pose(const Pose& p) { vec3(p.position), quat(p.orientation); }
    /// A u32 length, then the bytes.
    void text(const std::string& s);
    void blob(std::span<const unsigned char> b);
    /// compute::encode_sample's 120 bytes.
    void sample(const ToolSample& s);
    /// A u32 count, then per record: kind u8, index u64, and a batch's u32 sample count and samples or a mark's
    /// serial u64 and rays u64 (batches and marks only).
    void records(std::span<const compute::JournalRecord> records);
    /// The message (the writer is spent).
    std::vector<unsigned char> take() { return std::move(bytes_); }

private:
    std::vector<unsigned char> bytes_;
    devices::net::Writer w_;
};

/// Reads one message, refusing it with tridex::Error "<from>: <field>: <what>" when it is truncated, holds a number
/// that is not finite, a length over the limits above, another magic ("not a tridex <what> message") or kind.
class MessageReader {
public:
    /// `what` names the message family in the magic's error ("cluster", "shared session").
    MessageReader(std::span<const unsigned char> b, const std::string& from, const unsigned char (&magic)[4],
                  std::uint8_t want_kind, const char* what);
    [[noreturn]] void fail(const std::string& field, const std::string& what) const;
    /// Refuses the message, naming `field`, when fewer than n bytes remain (before reserving room for them).
    void need(std::size_t n, const char* field) const;
    std::uint8_t u8(const char* field) { return checked(r_.u8(), 1, field); }
    std::uint32_t u32(const char* field) { return checked(r_.u32(), 4, field); }
    std::uint64_t u64(const char* field) { return checked(r_.u64(), 8, field); }
    double f64(const char* field) { return checked(r_.f64(), 8, field); }
    Vec3 vec3(const char* field);
    /// A quaternion of length near 1 (else refused).
    Quat quat(const char* field);
    Pose pose(const char* field);
    std::string text(const char* field);
    std::vector<unsigned char> blob(const char* field);
    /// A sample compute::decode_sample accepts, with finite time, position and tool sizes >= 0.
    ToolSample sample(const char* field);
    /// MessageWriter::records' layout.
    std::vector<compute::JournalRecord> records(const char* field);
    /// Refuses bytes after the message's end.
    void end() const;
    /// Who sent the message, as messages name it.
    const std::string& from() const { return from_; }

private:
    template <class T>
    T checked(T v, std::size_t n, const char* field) {
        if (r_.failed()) truncated(n, field);
        if (r_.non_finite()) fail(field, "not a finite number");
        return v;
    }
    [[noreturn]] void truncated(std::size_t n, const char* field) const;

    devices::net::Reader r_;
    std::size_t size_;
    std::string from_;
};

/// Where a late joiner's model stands in the stream (a shared session's welcome, a wall's late hello): the record the
/// stream goes on from, the undo history's steps, each site's last sample and the newest stroke closed
/// (app::SculptSnapshot's parts), to read into.
struct LateStartFields {
    std::uint64_t* first_record = nullptr;
    std::vector<unsigned char>* history = nullptr;
    std::vector<ToolSample>* prevs = nullptr;
    std::uint64_t* last_closed_serial = nullptr;
};

/// Writes a late start's fields in that order: u64, the history as a blob packed with zstd (empty: none), a u32 count
/// of samples and the samples, u64.
void write_late_start(MessageWriter& w, std::uint64_t first_record, const std::vector<unsigned char>& history,
                      const std::vector<ToolSample>& prevs, std::uint64_t last_closed_serial);
/// Reads them back; refuses (MessageReader::fail) a history that does not unpack or more samples than kMaxSites.
void read_late_start(MessageReader& r, const LateStartFields& f);

}  // namespace tridex::app
