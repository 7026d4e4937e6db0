// app/session/wire/message_io.cpp - the session messages' writer and checked reader.
#include "app/session/wire/message_io.hpp"

#include <cmath>
#include <cstring>
#include <iterator>

#include "compute/journal/journal_format.hpp"
#include "compute/journal/stream_pack.hpp"
#include "core/error.hpp"
#include "core/math.hpp"

namespace tridex::app {

MessageWriter::MessageWriter(const unsigned char (&magic)[4], std::uint8_t kind)
    : bytes_(std::begin(magic), std::end(magic)), w_(bytes_) {
    w_.u8(kind);
}

void MessageWriter::text(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    bytes_.insert(bytes_.end(), s.begin(), s.end());
}

void MessageWriter::blob(std::span<const unsigned char> b) {
    u32(static_cast<std::uint32_t>(b.size()));
    bytes_.insert(bytes_.end(), b.begin(), b.end());
}

void MessageWriter::sample(const ToolSample& s) {
    const std::size_t at = bytes_.size();
    bytes_.resize(at + compute::kJournalSampleBytes);
    compute::encode_sample(s, bytes_.data() + at);
}

void MessageWriter::records(std::span<const compute::JournalRecord> records) {
    u32(static_cast<std::uint32_t>(records.size()));
    for (const compute::JournalRecord& rec : records) {
        u8(static_cast<std::uint8_t>(rec.kind));
        u64(rec.index);
        if (rec.kind == compute::JournalKind::kBatch) {
            u32(static_cast<std::uint32_t>(rec.samples.size()));
            for (const ToolSample& s : rec.samples) sample(s);
        } else {
            u64(rec.serial);
            u64(rec.rays);
        }
    }
}

MessageReader::MessageReader(std::span<const unsigned char> b, const std::string& from, const unsigned char (&magic)[4],
                             std::uint8_t want_kind, const char* what)
    : r_(b.data(), b.size()), size_(b.size()), from_(from) {
    const std::uint8_t* m = r_.bytes(4);
    if (!m || std::memcmp(m, magic, 4) != 0) fail("magic", std::string("not a tridex ") + what + " message");
    const std::uint8_t kind = u8("kind");
    if (kind != want_kind)
        fail("kind", "expected kind " + std::to_string(static_cast<int>(want_kind)) + ", got " + std::to_string(kind));
}

void MessageReader::fail(const std::string& field, const std::string& what) const {
    throw Error(from_ + ": " + field + ": " + what);
}

void MessageReader::need(std::size_t n, const char* field) const {
    if (r_.remaining() < n) truncated(n, field);
}

Vec3 MessageReader::vec3(const char* field) {
    const double x = f64(field), y = f64(field), z = f64(field);
    return Vec3(x, y, z);
}

Quat MessageReader::quat(const char* field) {
    const double w = f64(field), x = f64(field), y = f64(field), z = f64(field);
    const Quat q(w, x, y, z);
    if (!(glm::length(q) > 0.5)) fail(field, "not a unit quaternion");
    return q;
}

Pose MessageReader::pose(const char* field) {
    Pose p;
    p.position = vec3(field);
    p.orientation = quat(field);
    return p;
}

std::string MessageReader::text(const char* field) {
    const std::uint32_t n = u32(field);
    if (n > kMaxMessageText) fail(field, "length " + std::to_string(n) + " over the limit");
    const std::uint8_t* p = checked(r_.bytes(n), n, field);
    return std::string(reinterpret_cast<const char*>(p), n);
}

std::vector<unsigned char> MessageReader::blob(const char* field) {
    const std::uint32_t n = u32(field);
    if (n > kMaxMessageBlob) fail(field, "length " + std::to_string(n) + " over the limit");
    const std::uint8_t* p = checked(r_.bytes(n), n, field);
    return std::vector<unsigned char>(p, p + n);
}

ToolSample MessageReader::sample(const char* field) {
    const std::uint8_t* p = checked(r_.bytes(compute::kJournalSampleBytes), compute::kJournalSampleBytes, field);
    ToolSample s;
    if (!compute::decode_sample(p, s)) fail(field, "a sample no writer writes");
    if (!std::isfinite(s.t_s) || !is_finite(s.position) || !std::isfinite(s.tool.radius_m) || s.tool.radius_m < 0.0 ||
        !std::isfinite(s.tool.length_m) || s.tool.length_m < 0.0)
        fail(field, "a sample with a non-finite or negative field");
    return s;
}

std::vector<compute::JournalRecord> MessageReader::records(const char* field) {
    const std::uint32_t n = u32(field);
    if (n > kMaxMessageRecords) fail(field, std::to_string(n) + " records, over the limit");
    std::vector<compute::JournalRecord> out;
    out.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i) {
        compute::JournalRecord rec;
        const std::uint8_t k = u8("record.kind");
        if (k < 1 || k > 4) fail("record.kind", "record " + std::to_string(i) + ": unknown kind " + std::to_string(k));
        rec.kind = static_cast<compute::JournalKind>(k);
        rec.index = u64("record.index");
        if (rec.kind == compute::JournalKind::kBatch) {
            const std::uint32_t ns = u32("record.samples");
            if (ns > kMaxRecordSamples) fail("record.samples", std::to_string(ns) + " samples, over the limit");
            need(static_cast<std::size_t>(ns) * compute::kJournalSampleBytes, "record.samples");
            rec.samples.reserve(ns);
            for (std::uint32_t s = 0; s < ns; ++s) rec.samples.push_back(sample("record.sample"));
        } else {
            rec.serial = u64("record.serial");
            rec.rays = u64("record.rays");
        }
        out.push_back(std::move(rec));
    }
    return out;
}

void MessageReader::end() const {
    if (!r_.at_end()) fail("end", std::to_string(r_.remaining()) + " bytes after the message");
}

void MessageReader::truncated(std::size_t n, const char* field) const {
    fail(field, "truncated message (" + std::to_string(size_) + " bytes, " + std::to_string(n) + " more needed at byte " +
                    std::to_string(size_ - r_.remaining()) + ")");
}

void write_late_start(MessageWriter& w, std::uint64_t first_record, const std::vector<unsigned char>& history,
                      const std::vector<ToolSample>& prevs, std::uint64_t last_closed_serial) {
    w.u64(first_record);
    w.blob(history.empty() ? history : compute::pack_bytes(history));
    w.u32(static_cast<std::uint32_t>(prevs.size()));
    for (const ToolSample& s : prevs) w.sample(s);
    w.u64(last_closed_serial);
}

void read_late_start(MessageReader& r, const LateStartFields& f) {
    *f.first_record = r.u64("first_record");
    const std::vector<unsigned char> packed = r.blob("history");
    if (!packed.empty()) *f.history = compute::unpack_bytes(packed, kMaxMessageBlob, r.from() + ": history");
    const std::uint32_t prevs = r.u32("prevs");
    if (prevs > kMaxSites) r.fail("prevs", std::to_string(prevs) + " samples, more than a session has sites");
    for (std::uint32_t i = 0; i < prevs; ++i) f.prevs->push_back(r.sample("prevs"));
    *f.last_closed_serial = r.u64("last_closed_serial");
}

}  // namespace tridex::app
