// tests/fuzz/fuzz_cluster_wire.cpp - libFuzzer target: the datagrams of a wall without mpirun
// (app/session/cluster/net_transport_wire.hpp) as either end takes them from a peer that may hold no key: each
// datagram's kind, then a control datagram's decoder or the data datagrams joined into messages. The input is a
// sequence of datagrams, each a little-endian u16 length and that many bytes. Decoders refuse bad input with
// tridex::Error; any other exception, a crash or a sanitizer report is a finding.
#include <cstdint>
#include <string>
#include <vector>

#include "app/session/cluster/net_transport_wire.hpp"
#include "core/error.hpp"

namespace wire = tridex::app::netwire;

/// One fuzz input as the datagrams of one peer, in order.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    wire::Inbox inbox;
    std::size_t at = 0;
    while (at + 2 <= size) {
        const std::size_t n = static_cast<std::size_t>(data[at]) | (static_cast<std::size_t>(data[at + 1]) << 8);
        at += 2;
        std::vector<std::uint8_t> d(data + at, data + at + std::min(n, size - at));
        at += d.size();
        try {
            const auto kind = wire::datagram_kind(d);
            if (!kind) continue;  // dropped, as the transports drop it
            if (*kind == wire::Kind::kControl) {
                const wire::Control c = wire::decode_control(d);
                if (c.type == wire::ControlType::kRefuse && c.reason.size() > wire::kMaxReasonBytes) __builtin_trap();
            } else {
                (void)inbox.push(d);
                (void)inbox.ack_due();
            }
        } catch (const tridex::Error&) {
            // refused, as the transports refuse it
        }
    }
    return 0;
}
