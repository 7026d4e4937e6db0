// devices/tracking/dtrack_receiver.cpp - the DTrack UDP receiver thread (POSIX datagram socket).
#include "devices/tracking/dtrack_receiver.hpp"

#include <cerrno>
#include <cstring>
#include <memory>
#include <vector>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "core/error.hpp"
#include "core/thread_name.hpp"

namespace tridex::devices {
DTrackReceiver::DTrackReceiver(int port, const std::string& bind_address) {
    const std::string what = "DTrack UDP port " + std::to_string(port);
    if (port < 0 || port > 65535) throw Error(what + ": must be 1..65535 (0: any free port)");
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    if (inet_pton(AF_INET, bind_address.c_str(), &addr.sin_addr) != 1)
        throw Error(what + ": bind address '" + bind_address + "' is not a dotted IPv4 address");
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) throw Error(what + ": cannot create a UDP socket: " + std::strerror(errno));
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
        const int e = errno;
        ::close(fd_);
        throw Error(what + " on " + bind_address + ": cannot bind: " + std::strerror(e));
    }
    socklen_t len = sizeof addr;
    ::getsockname(fd_, reinterpret_cast<sockaddr*>(&addr), &len);
    port_ = ntohs(addr.sin_port);
    frame_.bodies.reserve(kDTrackMaxId + 1);
    frame_.flysticks.reserve(kDTrackMaxId + 1);
    thread_ = std::thread([this] { run(); });
}

DTrackReceiver::~DTrackReceiver() {
    stop();
    if (fd_ >= 0) ::close(fd_);
}

void DTrackReceiver::stop() {
    stop_.store(true, std::memory_order_relaxed);
    if (thread_.joinable()) thread_.join();
}

DTrackReceiverStats DTrackReceiver::stats() const {
    DTrackReceiverStats s;
    s.datagrams = datagrams_.load(std::memory_order_acquire);  // first: the counts below include these datagrams
    s.accepted = accepted_.load(std::memory_order_relaxed);
    s.rejected = rejected_.load(std::memory_order_relaxed);
    s.bytes = bytes_.load(std::memory_order_relaxed);
    s.bodies_dropped = dropped_.load(std::memory_order_relaxed);
    s.socket_errors = socket_errors_.load(std::memory_order_relaxed);
    s.published = published_.load(std::memory_order_acquire);
    s.flysticks_dropped = flysticks_dropped_.load(std::memory_order_relaxed);
    for (std::size_t k = 0; k < s.by_reason.size(); ++k) s.by_reason[k] = by_reason_[k].load(std::memory_order_relaxed);
    return s;
}

void DTrackReceiver::handle(const char* data, std::size_t size, std::int64_t receipt_ns) {
    // A datagram is counted once it is accepted or rejected (release: a reader that sees the count sees those too).
    struct Count {
        DTrackReceiver& rx;
        std::size_t bytes;
        ~Count() {
            rx.bytes_.fetch_add(bytes, std::memory_order_relaxed);
            rx.datagrams_.fetch_add(1, std::memory_order_release);
        }
    } count{*this, size};
    const DTrackParseResult r = size > kDTrackMaxDatagram ? DTrackParseResult{DTrackReject::kTooLarge, 0}
                                                          : parse_dtrack_datagram(std::string_view(data, size), frame_);
    DTrackReject reason = r.reason;
    if (r.ok() && frame_.has_frame_counter) {
        const std::uint32_t fr = frame_.frame_counter;
        const bool behind =
            have_newest_ && fr < newest_fr_ && receipt_ns - newest_receipt_ns_ < kDTrackRestartGapNs;
        if (behind) {
            reason = DTrackReject::kReplayed;
        } else {
            have_newest_ = true;
            newest_fr_ = fr;
            newest_receipt_ns_ = receipt_ns;
        }
    }
    if (reason != DTrackReject::kNone) {
        rejected_.fetch_add(1, std::memory_order_relaxed);
        by_reason_[static_cast<std::size_t>(reason)].fetch_add(1, std::memory_order_relaxed);
        return;
    }
    const std::uint64_t n = accepted_.fetch_add(1, std::memory_order_relaxed) + 1;
    working_.accepted = n;
    for (const DTrackBody& b : frame_.bodies) {
        if (b.id >= kDTrackKeptBodies) {
            dropped_.fetch_add(1, std::memory_order_relaxed);
            continue;
        }
        DTrackBodySample& s = working_.bodies[static_cast<std::size_t>(b.id)];
        s.seen = true;
        s.body = b;
        s.frame_counter = frame_.has_frame_counter ? frame_.frame_counter : 0;
        s.receipt_ns = receipt_ns;
        s.datagram = n;
    }
    for (const DTrackFlystick& f : frame_.flysticks) {
        if (f.body.id >= kDTrackKeptFlysticks) {
            flysticks_dropped_.fetch_add(1, std::memory_order_relaxed);
            continue;
        }
        DTrackFlystickSample& s = working_.flysticks[static_cast<std::size_t>(f.body.id)];
        s.seen = true;
        s.flystick = f;
        s.frame_counter = frame_.has_frame_counter ? frame_.frame_counter : 0;
        s.receipt_ns = receipt_ns;
        s.datagram = n;
    }
}

void DTrackReceiver::run() {
    name_this_thread("tridex-dtrack");
    // One byte more than the largest datagram the parser takes, so that a longer one is seen as too large.
    std::vector<char> buf(kDTrackMaxDatagram + 1);
    while (!stop_.load(std::memory_order_relaxed)) {
        pollfd p{fd_, POLLIN, 0};
        const int ready = ::poll(&p, 1, 20);
        if (ready <= 0) continue;
        bool changed = false;
        for (;;) {
            const ssize_t got = ::recv(fd_, buf.data(), buf.size(), MSG_DONTWAIT | MSG_TRUNC);
            const std::int64_t t = dtrack_clock_ns();
            if (got < 0) {
                if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)
                    socket_errors_.fetch_add(1, std::memory_order_relaxed);
                break;
            }
            // MSG_TRUNC: `got` is the datagram's real length even when the buffer cut it.
            handle(buf.data(), static_cast<std::size_t>(got), t);
            changed = true;
        }
        if (changed) {
            for (TripleBuffer<DTrackBodyTable>& table : tables_) {
                table.back() = working_;
                table.publish();
            }
            published_.store(working_.accepted, std::memory_order_release);
        }
    }
}

}  // namespace tridex::devices
