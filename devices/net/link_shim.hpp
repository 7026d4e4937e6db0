// devices/net/link_shim.hpp - an in-process pair of DatagramLinks with injected one-way latency and loss on a
// clock the caller gives, so link experiments (tridex bench --link) and tests are deterministic.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <vector>

#include "devices/net/datagram_link.hpp"

namespace tridex::devices::net {

/// What the shim does to datagrams (both directions alike).
struct ShimConfig {
    double latency_s = 0.0;  ///< one-way delay added to every datagram, s (>= 0)
    double loss = 0.0;       ///< probability that an unreliable datagram is lost, [0, 1)
    /// A lost reliable datagram is retransmitted after one round trip plus this, s (so it arrives late, never
    /// out of order: later reliable datagrams wait behind it, as in ENet).
    double retransmit_extra_s = 0.001;
    std::uint32_t seed = 1;  ///< seed of the loss draws
};

/// Counters of one shim pair.
struct ShimStats {
    std::uint64_t sent = 0;       ///< datagrams queued (both ways)
    std::uint64_t lost = 0;       ///< unreliable datagrams dropped by the loss draw
    std::uint64_t resent = 0;     ///< reliable datagrams delayed by a retransmission
    std::uint64_t delivered = 0;  ///< datagrams handed to poll()
};

/// A connected pair of links (server end, client end) sharing one clock. Thread-safe (a mutex): the two ends
/// may be polled from different threads.
class LinkShim {
public:
    /// clock: seconds, non-decreasing (a simulation's time, or a monotonic clock). Throws tridex::Error naming the
    /// field when latency_s < 0 or loss is outside [0, 1).
    LinkShim(ShimConfig cfg, std::function<double()> clock);
    ~LinkShim();
    LinkShim(const LinkShim&) = delete;
    LinkShim& operator=(const LinkShim&) = delete;

    /// The server's end (polled by a DeviceServer) and the client's end (the net driver's). Each may be taken
    /// once (the shim keeps running while the ends live; destroying an end disconnects it).
    std::unique_ptr<DatagramLink> server_end();
    std::unique_ptr<DatagramLink> client_end();
    /// Cuts (true) or restores (false) the link: while cut, nothing is delivered, both ends see kDisconnected,
    /// and on restoring both see kConnected (a dead or restarted server).
    void set_cut(bool cut);
    /// The counters so far.
    ShimStats stats() const;

private:
    friend class ShimEnd;
    struct InFlight {
        double due_s = 0.0;
        std::vector<std::uint8_t> bytes;
        bool control = false;  // a connect/disconnect notice, not data
        bool connect = false;
    };
    void send(int from, const std::vector<std::uint8_t>& bytes, bool reliable);
    bool poll(int at, LinkEvent& ev);
    bool connected(int end) const;

    ShimConfig cfg_;
    std::function<double()> clock_;
    mutable std::mutex mutex_;
    std::deque<InFlight> queue_[2];  // queue_[i]: datagrams on their way to end i
    double last_reliable_due_[2] = {0.0, 0.0};
    std::mt19937 rng_;
    std::uniform_real_distribution<double> uniform_{0.0, 1.0};
    bool cut_ = false;
    bool attached_[2] = {false, false};
    ShimStats stats_;
    std::string where_[2] = {"shim:server", "shim:client"};
};

}  // namespace tridex::devices::net
