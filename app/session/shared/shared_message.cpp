// app/session/shared/shared_message.cpp - encoding and checked decoding of a shared session's messages.
#include "app/session/shared/shared_message.hpp"

#include "app/session/wire/message_io.hpp"
#include "app/session/wire/presence_wire.hpp"
#include "compute/journal/journal_format.hpp"
#include "compute/journal/stream_pack.hpp"
#include "core/error.hpp"

namespace tridex::app {

namespace {

constexpr unsigned char kMagic[4] = {'T', 'D', 'X', 'S'};

MessageWriter writer(SharedKind k) { return MessageWriter(kMagic, static_cast<std::uint8_t>(k)); }
MessageReader reader(std::span<const unsigned char> b, const std::string& from, SharedKind k) {
    return MessageReader(b, from, kMagic, static_cast<std::uint8_t>(k), "shared session");
}

SculptRequest request_of(MessageReader& r, const char* field) {
    const std::uint8_t v = r.u8(field);
    if (v > static_cast<std::uint8_t>(SculptRequest::kEndStroke)) r.fail(field, "not an undo, redo or stroke close");
    return static_cast<SculptRequest>(v);
}

}  // namespace

SharedKind shared_kind(std::span<const unsigned char> b, const std::string& from) {
    if (b.size() < 5 || b[0] != kMagic[0] || b[1] != kMagic[1] || b[2] != kMagic[2] || b[3] != kMagic[3])
        throw Error(from + ": not a tridex shared session message");
    if (b[4] < 1 || b[4] > static_cast<unsigned char>(SharedKind::kRecordsPacked))
        throw Error(from + ": kind: unknown kind " + std::to_string(b[4]));
    return static_cast<SharedKind>(b[4]);
}

std::vector<unsigned char> encode_join(const JoinMessage& m) {
    MessageWriter w = writer(SharedKind::kJoin);
    w.u32(m.protocol);
    w.text(m.name);
    w.vec3(m.colour);
    w.u8(m.from_start ? 1 : 0);
    return w.take();
}

JoinMessage decode_join(std::span<const unsigned char> b, const std::string& from) {
    MessageReader r = reader(b, from, SharedKind::kJoin);
    JoinMessage m;
    m.protocol = r.u32("protocol");
    m.name = read_site_name(r, "name", false);
    m.colour = read_colour(r, "colour");
    const std::uint8_t from_start = r.u8("from_start");
    if (from_start > 1) r.fail("from_start", "not 0 or 1");
    m.from_start = from_start != 0;
    r.end();
    return m;
}

std::vector<unsigned char> encode_welcome(const WelcomeMessage& m) {
    MessageWriter w = writer(SharedKind::kWelcome);
    w.u8(m.site);
    w.text(m.host_name);
    w.text(m.spec_json);
    w.blob(m.model_tdx);
    w.u64(m.initial_digest);
    write_late_start(w, m.first_record, m.history, m.prevs, m.last_closed_serial);
    return w.take();
}

WelcomeMessage decode_welcome(std::span<const unsigned char> b, const std::string& from) {
    MessageReader r = reader(b, from, SharedKind::kWelcome);
    WelcomeMessage m;
    m.site = read_site(r, "site");
    if (m.site == 0) r.fail("site", "site 0 is the host's");
    m.host_name = read_site_name(r, "host_name", false);
    m.spec_json = r.text("spec");
    m.model_tdx = r.blob("model");
    if (m.model_tdx.empty()) r.fail("model", "no model");
    m.initial_digest = r.u64("initial_digest");
    read_late_start(r, {&m.first_record, &m.history, &m.prevs, &m.last_closed_serial});
    r.end();
    return m;
}

std::vector<unsigned char> encode_samples(std::span<const ToolSample> samples) {
    MessageWriter w = writer(SharedKind::kSamples);
    w.u32(static_cast<std::uint32_t>(samples.size()));
    for (const ToolSample& s : samples) w.sample(s);
    return w.take();
}

std::vector<ToolSample> decode_samples(std::span<const unsigned char> b, const std::string& from) {
    MessageReader r = reader(b, from, SharedKind::kSamples);
    const std::uint32_t n = r.u32("samples");
    if (n > kMaxRecordSamples) r.fail("samples", std::to_string(n) + " samples, over the limit");
    r.need(static_cast<std::size_t>(n) * compute::kJournalSampleBytes, "samples");
    std::vector<ToolSample> out;
    out.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i) out.push_back(r.sample("sample"));
    r.end();
    return out;
}

std::vector<unsigned char> encode_request(SculptRequest q) {
    MessageWriter w = writer(SharedKind::kRequest);
    w.u8(static_cast<std::uint8_t>(q));
    return w.take();
}

SculptRequest decode_request(std::span<const unsigned char> b, const std::string& from) {
    MessageReader r = reader(b, from, SharedKind::kRequest);
    const SculptRequest q = request_of(r, "request");
    r.end();
    return q;
}

std::vector<unsigned char> encode_records(const RecordsMessage& m) {
    MessageWriter w = writer(SharedKind::kRecords);
    w.u8(m.check_digest ? 1 : 0);
    w.u64(m.check_digest.value_or(0));
    w.u32(m.check_after);
    w.records(m.records);
    std::vector<unsigned char> plain = w.take();
    if (plain.size() < kPackRecordsFromBytes) return plain;
    MessageWriter packed = writer(SharedKind::kRecordsPacked);
    std::vector<unsigned char> out = packed.take();
    const std::vector<unsigned char> frame = compute::pack_bytes(plain);
    if (out.size() + frame.size() >= plain.size()) return plain;
    out.insert(out.end(), frame.begin(), frame.end());
    return out;
}

RecordsMessage decode_records(std::span<const unsigned char> b, const std::string& from) {
    if (b.size() > 4 && b[4] == static_cast<unsigned char>(SharedKind::kRecordsPacked)) {
        (void)reader(b, from, SharedKind::kRecordsPacked);  // the magic
        const std::vector<unsigned char> plain = compute::unpack_bytes(b.subspan(5), kMaxMessageBlob, from + ": packed records");
        if (plain.size() > 4 && plain[4] == static_cast<unsigned char>(SharedKind::kRecordsPacked))
            throw Error(from + ": packed records hold packed records");
        return decode_records(plain, from);
    }
    MessageReader r = reader(b, from, SharedKind::kRecords);
    RecordsMessage m;
    const std::uint8_t has = r.u8("check");
    if (has > 1) r.fail("check", "not 0 or 1");
    const std::uint64_t digest = r.u64("check_digest");
    m.check_after = r.u32("check_after");
    if (has) m.check_digest = digest;
    m.records = r.records("records");
    if (m.check_digest && m.check_after > m.records.size()) r.fail("check_after", "past the records");
    r.end();
    return m;
}

std::vector<unsigned char> encode_refused(const RefusedMessage& m) {
    MessageWriter w = writer(SharedKind::kRefused);
    w.u8(static_cast<std::uint8_t>(m.request));
    w.u8(m.by_site);
    w.text(m.by_name);
    return w.take();
}

RefusedMessage decode_refused(std::span<const unsigned char> b, const std::string& from) {
    MessageReader r = reader(b, from, SharedKind::kRefused);
    RefusedMessage m;
    m.request = request_of(r, "request");
    m.by_site = read_site(r, "by_site");
    m.by_name = read_site_name(r, "by_name", true);
    r.end();
    return m;
}

std::vector<unsigned char> encode_presence(const PresenceMessage& m) {
    MessageWriter w = writer(SharedKind::kPresence);
    write_presence(w, m);
    return w.take();
}

PresenceMessage decode_presence(std::span<const unsigned char> b, const std::string& from) {
    MessageReader r = reader(b, from, SharedKind::kPresence);
    PresenceMessage m = read_presence(r);
    r.end();
    return m;
}

std::vector<unsigned char> encode_end(const EndMessage& m) {
    MessageWriter w = writer(SharedKind::kEnd);
    w.u64(m.digest);
    w.u64(m.records);
    w.text(m.reason);
    return w.take();
}

EndMessage decode_end(std::span<const unsigned char> b, const std::string& from) {
    MessageReader r = reader(b, from, SharedKind::kEnd);
    EndMessage m;
    m.digest = r.u64("digest");
    m.records = r.u64("records");
    m.reason = r.text("reason");
    r.end();
    return m;
}

}  // namespace tridex::app
