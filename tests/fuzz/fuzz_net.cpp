// tests/fuzz/fuzz_net.cpp - libFuzzer target: the device server's datagrams (devices/net): decode_header, then
// the payload decoder of the header's type, as the server and the session dispatch them. Decoders return a drop
// reason and never throw: any exception is a finding.
#include <cstdint>
#include <string>

#include "core/active_surface.hpp"
#include "devices/net/link_wire.hpp"
#include "devices/net/surface_codec.hpp"

namespace net = tridex::devices::net;

namespace {

/// The payload decoder for the header's type; kNone when the datagram was accepted.
net::DropReason decode_payload(const std::uint8_t* p, std::size_t n, net::MsgType type) {
    static tridex::ActiveSurface surface;  // large: one per process, as the server keeps one
    switch (type) {
        case net::MsgType::kHello: {
            net::Hello m;
            return net::decode(p, n, m);
        }
        case net::MsgType::kWelcome: {
            net::Welcome m;
            return net::decode(p, n, m);
        }
        case net::MsgType::kRefuse: {
            std::string reason;
            return net::decode_refuse(p, n, reason);
        }
        case net::MsgType::kState: {
            net::StateMsg m;
            return net::decode(p, n, m);
        }
        case net::MsgType::kForce: {
            net::ForceMsg m;
            return net::decode(p, n, m);
        }
        case net::MsgType::kSurface: return net::decode_surface(p, n, surface);
        case net::MsgType::kContact: {
            net::ContactMsg m;
            return net::decode(p, n, m);
        }
        case net::MsgType::kHeartbeat: return net::DropReason::kNone;
    }
    return net::DropReason::kNone;
}

}  // namespace

/// One fuzz input as one datagram.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    net::Header h;
    const net::DropReason head = net::decode_header(data, size, h);
    if (head != net::DropReason::kNone && head != net::DropReason::kVersion) return 0;
    if (head == net::DropReason::kVersion && h.type != net::MsgType::kRefuse) return 0;
    decode_payload(data, size, h.type);
    return 0;
}
