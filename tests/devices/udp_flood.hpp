// tests/devices/udp_flood.hpp - a flood of bad datagrams for the network inputs' tests: random bytes, forged ENet
// datagrams (a connect, and a "replayed" unreliable send under a connected peer's id, from another address) and the
// kernel's count of datagrams a UDP port dropped because its socket buffer was full.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace tridex::test {

/// Sends datagrams to 127.0.0.1:port from its own socket (so from another address than any session).
class UdpFlooder {
public:
    explicit UdpFlooder(int port, std::uint64_t seed = 1) : rng_(seed) {
        fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
        if (fd_ < 0) throw std::runtime_error("socket");
        to_.sin_family = AF_INET;
        to_.sin_port = htons(static_cast<std::uint16_t>(port));
        to_.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    }
    ~UdpFlooder() { ::close(fd_); }
    UdpFlooder(const UdpFlooder&) = delete;
    UdpFlooder& operator=(const UdpFlooder&) = delete;

    /// Sends `bytes` as one datagram; true when the kernel took it.
    bool send(const std::vector<std::uint8_t>& bytes) {
        return ::sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to_), sizeof to_) ==
               static_cast<ssize_t>(bytes.size());
    }
    /// 1..max_size random bytes.
    std::vector<std::uint8_t> random_bytes(std::size_t max_size = 200) {
        std::vector<std::uint8_t> b(1 + rng_() % max_size);
        for (auto& c : b) c = static_cast<std::uint8_t>(rng_() & 0xFF);
        return b;
    }
    /// An ENet datagram as a connected peer 0 sends it (ENet protocol.h: peer id 0 with the sent-time flag, sent
    /// time, then an unreliable send on channel 1 with a payload of `payload` bytes): what a replay of a session's
    /// state datagrams from another address looks like.
    std::vector<std::uint8_t> enet_replayed_send(std::size_t payload = 48) {
        std::vector<std::uint8_t> b = {0x80, 0x00, 0x12, 0x34,         // peer 0, sent time
                                       0x07, 0x01, 0x00, 0x05,         // SEND_UNRELIABLE, channel 1, reliable seq
                                       0x00, 0x09,                     // unreliable seq
                                       0x00, static_cast<std::uint8_t>(payload)};
        for (std::size_t i = 0; i < payload; ++i) b.push_back(static_cast<std::uint8_t>(rng_() & 0xFF));
        return b;
    }
    /// An ENet connect (ENet protocol.h: peer id 0xFFF with the sent-time flag, the CONNECT command with the
    /// acknowledge flag, then the connect body, zeros here).
    std::vector<std::uint8_t> enet_connect() {
        std::vector<std::uint8_t> b = {0x8F, 0xFF, 0x00, 0x01, 0x82, 0xFF, 0x00, 0x01};
        b.resize(b.size() + 40, 0);
        return b;
    }

private:
    int fd_ = -1;
    sockaddr_in to_{};
    std::mt19937_64 rng_;
};

/// Datagrams the kernel dropped at the UDP socket bound to 127.0.0.1:port (or 0.0.0.0:port) of any process, from
/// /proc/net/udp's `drops` column; 0 when no such socket is open.
inline std::uint64_t udp_drops(int port) {
    std::ifstream f("/proc/net/udp");
    std::string line;
    std::getline(f, line);  // header
    std::uint64_t drops = 0;
    char want[8];
    std::snprintf(want, sizeof want, "%04X", port);
    while (std::getline(f, line)) {
        std::istringstream in(line);
        std::string sl, local, field;
        in >> sl >> local;
        const auto colon = local.find(':');
        if (colon == std::string::npos || local.substr(colon + 1) != want) continue;
        std::vector<std::string> rest;
        while (in >> field) rest.push_back(field);
        if (!rest.empty()) drops += std::stoull(rest.back());
    }
    return drops;
}

}  // namespace tridex::test
