// tests/fuzz/fuzz_dtrack.cpp - libFuzzer target: parse_dtrack_datagram on one DTrack ASCII datagram. The parser
// never throws: any exception is a finding, and so is an accepted frame whose tracked pose is not finite.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "devices/tracking/dtrack_parser.hpp"
#include "tests/fuzz/fuzz_support.hpp"

namespace {

/// Aborts (a finding) when a tracked body's pose has a non-finite position or orientation.
void require_finite_pose(const tridex::devices::DTrackBody& body) {
    if (!body.tracked()) return;
    const tridex::Pose p = body.pose();
    const double sum = p.position.x + p.position.y + p.position.z + p.orientation.w + p.orientation.x +
                       p.orientation.y + p.orientation.z;
    if (std::isfinite(sum)) return;
    std::fprintf(stderr, "tridex fuzz: an accepted DTrack body %d has a non-finite pose\n", body.id);
    std::abort();
}

}  // namespace

/// One fuzz input as one datagram; the frame is reused across inputs, as the receiver reuses it.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static tridex::devices::DTrackFrame frame;
    if (!tridex::devices::parse_dtrack_datagram(tridex::fuzz::as_text(data, size), frame).ok()) return 0;
    for (const auto& body : frame.bodies) require_finite_pose(body);
    for (const auto& stick : frame.flysticks) require_finite_pose(stick.body);
    return 0;
}
