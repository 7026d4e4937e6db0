// app/session/cluster/net_transport_wire.cpp - a network wall's datagrams (messages split and joined, control
// datagrams written and read) and the network thread's loop.
#include "app/session/cluster/net_transport_wire.hpp"

#include <enet/enet.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "core/error.hpp"

namespace tridex::app::netwire {

namespace {

constexpr char kMagic[4] = {'T', 'D', 'X', 'W'};
constexpr std::size_t kControlHeader = 1 + sizeof kMagic + 2 + 1;  // kind, magic, version, type

void put_u16(std::vector<std::uint8_t>& out, std::uint16_t v) {
    out.push_back(static_cast<std::uint8_t>(v));
    out.push_back(static_cast<std::uint8_t>(v >> 8));
}

void put_u64(std::vector<std::uint8_t>& out, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

std::uint64_t get_le(const std::vector<std::uint8_t>& d, std::size_t at, int bytes) {
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v |= static_cast<std::uint64_t>(d[at + static_cast<std::size_t>(i)]) << (8 * i);
    return v;
}

std::vector<std::uint8_t> control(ControlType type) {
    std::vector<std::uint8_t> out(kControlHeader);
    out[0] = static_cast<std::uint8_t>(Kind::kControl);
    std::memcpy(out.data() + 1, kMagic, sizeof kMagic);
    out[5] = static_cast<std::uint8_t>(kProtocol);
    out[6] = static_cast<std::uint8_t>(kProtocol >> 8);
    out[7] = static_cast<std::uint8_t>(type);
    return out;
}

// The number of field bytes of a control type, or -1 for a variable length (a refusal's reason).
int field_bytes(ControlType type) {
    switch (type) {
        case ControlType::kClaim:
        case ControlType::kAccept: return 2;
        case ControlType::kRefuse: return -1;
        case ControlType::kAck: return 16;
        case ControlType::kAbort: return 4;
    }
    return -2;
}

}  // namespace

std::optional<Kind> datagram_kind(const std::vector<std::uint8_t>& datagram) {
    if (datagram.empty()) return std::nullopt;
    switch (static_cast<Kind>(datagram[0])) {
        case Kind::kDataMore:
        case Kind::kDataLast:
        case Kind::kControl: return static_cast<Kind>(datagram[0]);
    }
    return std::nullopt;
}

std::size_t chunk_count(std::size_t bytes) { return bytes == 0 ? 1 : (bytes + kMaxChunkBytes - 1) / kMaxChunkBytes; }

void make_chunk(const std::vector<unsigned char>& message, std::size_t i, std::vector<std::uint8_t>& out) {
    const std::size_t begin = std::min(message.size(), i * kMaxChunkBytes);
    const std::size_t end = std::min(message.size(), begin + kMaxChunkBytes);
    const bool last = i + 1 >= chunk_count(message.size());
    out.resize(1 + (end - begin));
    out[0] = static_cast<std::uint8_t>(last ? Kind::kDataLast : Kind::kDataMore);
    if (end > begin) std::memcpy(out.data() + 1, message.data() + begin, end - begin);
}

std::vector<std::uint8_t> encode_claim(int rank) {
    std::vector<std::uint8_t> out = control(ControlType::kClaim);
    put_u16(out, static_cast<std::uint16_t>(rank));
    return out;
}

std::vector<std::uint8_t> encode_accept(int rank) {
    std::vector<std::uint8_t> out = control(ControlType::kAccept);
    put_u16(out, static_cast<std::uint16_t>(rank));
    return out;
}

std::vector<std::uint8_t> encode_refuse(const std::string& reason) {
    std::vector<std::uint8_t> out = control(ControlType::kRefuse);
    out.insert(out.end(), reason.begin(),
               reason.begin() + static_cast<std::ptrdiff_t>(std::min(reason.size(), kMaxReasonBytes)));
    return out;
}

std::vector<std::uint8_t> encode_ack(std::uint64_t count, std::uint64_t bytes) {
    std::vector<std::uint8_t> out = control(ControlType::kAck);
    put_u64(out, count);
    put_u64(out, bytes);
    return out;
}

std::vector<std::uint8_t> encode_abort(int code) {
    std::vector<std::uint8_t> out = control(ControlType::kAbort);
    const auto v = static_cast<std::uint32_t>(code);
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    return out;
}

Control decode_control(const std::vector<std::uint8_t>& d) {
    if (d.size() < kControlHeader)
        throw Error("a control datagram of " + std::to_string(d.size()) + " bytes (at least " +
                    std::to_string(kControlHeader) + ")");
    if (d[0] != static_cast<std::uint8_t>(Kind::kControl) || std::memcmp(d.data() + 1, kMagic, sizeof kMagic) != 0)
        throw Error("a control datagram without the TDXW mark");
    Control c;
    c.version = static_cast<std::uint16_t>(get_le(d, 5, 2));
    c.type = static_cast<ControlType>(d[7]);
    const int fields = field_bytes(c.type);
    if (fields == -2) throw Error("a control datagram of unknown type " + std::to_string(d[7]));
    if (c.version != kProtocol) return c;
    const std::size_t n = d.size() - kControlHeader;
    if (fields >= 0 && n != static_cast<std::size_t>(fields))
        throw Error("a control datagram of type " + std::to_string(d[7]) + " with " + std::to_string(n) +
                    " field bytes (" + std::to_string(fields) + " expected)");
    switch (c.type) {
        case ControlType::kClaim:
        case ControlType::kAccept: c.rank = static_cast<int>(get_le(d, kControlHeader, 2)); break;
        case ControlType::kRefuse:
            if (n > kMaxReasonBytes) throw Error("a refusal of " + std::to_string(n) + " bytes");
            c.reason.assign(d.begin() + kControlHeader, d.end());
            break;
        case ControlType::kAck:
            c.count = get_le(d, kControlHeader, 8);
            c.bytes = get_le(d, kControlHeader + 8, 8);
            break;
        case ControlType::kAbort:
            c.code = static_cast<int>(static_cast<std::uint32_t>(get_le(d, kControlHeader, 4)));
            break;
    }
    return c;
}

std::optional<Message> Inbox::push(std::vector<std::uint8_t>& datagram) {
    const bool last = datagram[0] == static_cast<std::uint8_t>(Kind::kDataLast);
    const std::size_t n = datagram.size() - 1;
    if (partial_.size() + n > kMaxMessageBytes)
        throw Error("a message over " + std::to_string(kMaxMessageBytes >> 20) + " MiB");
    bytes_ += n;
    if (!last) {
        partial_.insert(partial_.end(), datagram.begin() + 1, datagram.end());
        return std::nullopt;
    }
    ++messages_;
    if (partial_.empty()) {  // a message of one datagram: no copy into partial_
        datagram.erase(datagram.begin());
        return Message(std::move(datagram));
    }
    partial_.insert(partial_.end(), datagram.begin() + 1, datagram.end());
    Message done;
    done.swap(partial_);
    return done;
}

std::optional<std::vector<std::uint8_t>> Inbox::ack_due() {
    if (messages_ == acked_messages_ && bytes_ == acked_bytes_) return std::nullopt;
    acked_messages_ = messages_;
    acked_bytes_ = bytes_;
    return encode_ack(messages_, bytes_);
}

void Outbox::add(std::deque<Message>& more) {
    for (Message& m : more) queue_.push_back(std::move(m));
    more.clear();
}

bool Outbox::pump(devices::net::DatagramLink& link, std::vector<std::uint8_t>& scratch) {
    bool any = false;
    while (!queue_.empty() && sent_ - acked_ < kWindowBytes) {
        const Message& m = queue_.front();
        make_chunk(m, chunk_, scratch);
        link.send(scratch, true);
        sent_ += scratch.size() - 1;
        any = true;
        if (++chunk_ < chunk_count(m.size())) continue;
        queue_.pop_front();
        chunk_ = 0;
    }
    if (queue_.empty() && abort_) {
        link.send(encode_abort(*abort_), true);
        abort_.reset();
        any = true;
    }
    return any;
}

std::string enet_version() {
    return std::to_string(ENET_VERSION_MAJOR) + "." + std::to_string(ENET_VERSION_MINOR) + "." +
           std::to_string(ENET_VERSION_PATCH);
}

std::string seconds_text(double s) {
    char text[32];
    std::snprintf(text, sizeof text, "%g s", std::round(std::max(0.0, s) * 10.0) / 10.0);
    return text;
}

std::string reason_of(const std::exception& e) {
    const std::string m = e.what();
    const auto at = m.find(": ");
    return at == std::string::npos ? m : m.substr(at + 2);
}

void NetTransport::run() {
    while (!stop_.load()) {
        bool busy = false;
        try {
            busy = service();
        } catch (const std::exception& e) {
            thread_failed(e.what());
        }
        if (!busy) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

}  // namespace tridex::app::netwire
