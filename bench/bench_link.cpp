// bench/bench_link.cpp - the wall through the link shim, every mode x latency x loss, on one simulated clock.
#include "bench/bench_link.hpp"
#include "bench/bench_registry.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/support/json_file.hpp"
#include "bench/bench_wall.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "devices/net/link_shim.hpp"
#include "devices/net/net_device.hpp"
#include "devices/simulated_device.hpp"
#include "haptics/device_server.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::bench {
using namespace tridex::app;  // bench sits above app: sessions, stats and JSON files

namespace {

namespace net = devices::net;

constexpr double kDt = 1e-3;
constexpr double kRunS = 2.0;
constexpr double kHoldFrom = 0.9, kHoldTo = 1.35;  // inside the hand's still hold (0.4-1.4 s), after the press settles

struct RunResult {
    LinkBenchRow row;
    std::vector<double> force_z;  // applied force per device step, N
};

RunResult run_case(const LinkBenchOptions& bo, net::RenderingMode mode, double latency_s, double loss, std::uint32_t seed) {
    double now = 0.0;
    const auto clock = [&now] { return now; };
    net::ShimConfig sc;
    sc.latency_s = latency_s;
    sc.loss = loss;
    sc.seed = seed;
    net::LinkShim shim(sc, clock);
    devices::SimulatedHandParams hand;
    hand.substeps = 10;  // close to the continuous plant, so the sampled wall's energy shows
    devices::SimulatedDevice device(devices::DeviceProfile::phantom_omni(), bench_wall_press(bo.press_depth_m), hand, kDt);
    auto server_link = shim.server_end();
    haptics::DeviceServerConfig scfg;
    scfg.clock = clock;
    haptics::DeviceServer server(device, *server_link, scfg);
    net::NetDeviceOptions o;
    o.mode = mode;
    o.clock = clock;
    o.link_thread = false;  // the simulated clock is this thread's: service() is called per tick below
    net::NetDevice client(shim.client_end(), o);

    haptics::HapticLoopConfig cfg;
    cfg.contact.stiffness_n_per_m = bo.stiffness_n_per_m;
    cfg.contact.damping_n_s_per_m = 0.5;
    cfg.contact.tool_radius_m = 0.0;
    cfg.request_realtime = false;
    net::ContactMsg contact;
    contact.stiffness_n_per_m = cfg.contact.stiffness_n_per_m;
    contact.damping_n_s_per_m = cfg.contact.damping_n_s_per_m;
    contact.tool_radius_m = 0.0;
    contact.ewma_alpha = cfg.ewma_alpha;
    client.set_contact(contact);
    for (int i = 0; !client.handshake(); ++i) {
        if (i > 10000) throw Error("bench --link: the shimmed session was never welcomed");
        now += kDt;
        server.tick(now);
    }
    TripleBuffer<ActiveSurface> surface;
    surface.back() = *bench_wall_surface();
    surface.publish();
    client.observe_surface(*bench_wall_surface());  // as the sculpt thread offers it
    SpscRing<ToolSample> samples(8192);
    haptics::HapticLoop loop(client, surface, samples, cfg);

    RunResult r;
    r.row.mode = net::to_string(mode);
    r.row.latency_ms = latency_s * 1e3;
    r.row.loss = loss;
    const auto steps = static_cast<std::size_t>(std::llround(kRunS / kDt));
    r.force_z.assign(steps, 0.0);
    double energy = 0.0, depth = 0.0, hold_lo = 1e9, hold_hi = -1e9;
    const std::uint64_t updates0 = server.stats().force_updates;
    const std::size_t step0 = device.steps();
    ToolSample drained;
    std::size_t iterations = 0;
    while (device.steps() - step0 < steps) {
        if (++iterations > 4 * steps) throw Error("bench --link: the server stopped stepping its device");
        now += kDt;
        const Vec3 f_applied = device.last_force_n();  // acts during the step the server's read takes
        const std::size_t before = device.steps();
        server.tick(now);
        loop.step(now);
        client.service();
        while (samples.try_pop(drained)) {
        }
        if (device.steps() == before) continue;  // the server rested its device this tick (a silent link)
        const std::size_t k = device.steps() - step0 - 1;
        energy -= glm::dot(f_applied, device.velocity_m_s()) * kDt;
        depth = std::max(depth, -device.position_m().z);
        const double fz = device.last_force_n().z;
        r.force_z[k] = fz;
        const double t = device.time_s();
        if (t >= kHoldFrom && t <= kHoldTo) {
            hold_lo = std::min(hold_lo, fz);
            hold_hi = std::max(hold_hi, fz);
        }
    }
    loop.stop();
    const devices::DeviceLinkStats ls = client.link_stats();
    r.row.rate_hz = static_cast<double>(server.stats().force_updates - updates0) / kRunS;
    r.row.max_penetration_m = depth;
    r.row.passivity_energy_j = energy;
    r.row.hold_force_p2p_n = hold_hi - hold_lo;
    r.row.stable = energy > -1e-3 && r.row.hold_force_p2p_n < 0.2;
    r.row.rtt_median_us = ls.rtt_median_us;
    r.row.lost = ls.lost;
    return r;
}

}  // namespace

std::vector<LinkBenchRow> run_link_bench(const LinkBenchOptions& o) {
    if (o.latencies_ms.empty() || o.losses.empty()) throw Error("bench --link: no latencies or losses to run");
    for (double l : o.latencies_ms)
        if (!(l >= 0.0 && l <= 200.0)) throw Error("bench --link: latency " + format_number(l) + " ms is not in [0, 200]");
    for (double p : o.losses)
        if (!(p >= 0.0 && p <= 0.5)) throw Error("bench --link: loss " + format_number(p) + " is not in [0, 0.5]");
    if (!(o.stiffness_n_per_m > 0.0 && o.stiffness_n_per_m <= 1e5))
        throw Error("bench --link: wall stiffness " + format_number(o.stiffness_n_per_m) + " N/m is not in (0, 1e5]");
    if (!(o.press_depth_m > 0.0 && o.press_depth_m <= 0.01))
        throw Error("bench --link: press depth " + format_number(o.press_depth_m) + " m is not in (0, 0.01]");
    std::filesystem::create_directories(o.out);
    std::vector<LinkBenchRow> rows;
    std::printf("wall %.0f N/m, hand target %.1f mm in; simulated PHANTOM Omni, 1 kHz server and session loops\n",
                o.stiffness_n_per_m, o.press_depth_m * 1e3);
    std::printf("%-12s %7s %6s %8s %10s %10s %11s %9s %7s %9s %6s\n", "mode", "lat_ms", "loss", "rate_hz", "pen_mm",
                "F_rms_N", "energy_mJ", "p2p_N", "stable", "rtt_us", "lost");
    for (net::RenderingMode mode : {net::RenderingMode::kDistributed, net::RenderingMode::kLocal}) {
        const RunResult ref = run_case(o, mode, 0.0, 0.0, 1);
        for (double lat : o.latencies_ms)
            for (double loss : o.losses) {
                const std::uint32_t seed = 1 + static_cast<std::uint32_t>(lat * 10.0) * 131u + static_cast<std::uint32_t>(loss * 1000.0);
                RunResult r = (lat == 0.0 && loss == 0.0) ? ref : run_case(o, mode, lat * 1e-3, loss, seed);
                double se = 0.0;
                for (std::size_t k = 0; k < r.force_z.size(); ++k) se += (r.force_z[k] - ref.force_z[k]) * (r.force_z[k] - ref.force_z[k]);
                r.row.force_rms_error_n = std::sqrt(se / static_cast<double>(r.force_z.size()));
                const LinkBenchRow& w = r.row;
                std::printf("%-12s %7.1f %6.2f %8.0f %10.3f %10.4f %11.3f %9.3f %7s %9.0f %6llu\n", w.mode.c_str(),
                            w.latency_ms, w.loss, w.rate_hz, w.max_penetration_m * 1e3, w.force_rms_error_n,
                            w.passivity_energy_j * 1e3, w.hold_force_p2p_n, w.stable ? "yes" : "NO", w.rtt_median_us,
                            static_cast<unsigned long long>(w.lost));
                rows.push_back(w);
            }
    }
    nlohmann::json j = nlohmann::json::array();
    for (const LinkBenchRow& w : rows)
        j.push_back({{"mode", w.mode},
                     {"latency_ms", w.latency_ms},
                     {"loss", w.loss},
                     {"rate_hz", w.rate_hz},
                     {"max_penetration_m", w.max_penetration_m},
                     {"force_rms_error_n", w.force_rms_error_n},
                     {"passivity_energy_j", w.passivity_energy_j},
                     {"hold_force_p2p_n", w.hold_force_p2p_n},
                     {"stable", w.stable},
                     {"rtt_median_us", w.rtt_median_us},
                     {"lost", w.lost}});
    const std::string path = (std::filesystem::path(o.out) / "link_bench.json").string();
    write_json_file(path, j);
    std::printf("wrote %s\n", path.c_str());
    return rows;
}

namespace {

BenchRun setup_link_bench(CLI::App&) {
    return [](const BenchCommon& c) {
        LinkBenchOptions o;
        o.out = c.out;
        run_link_bench(o);
    };
}

const BenchmarkRegistration kRegistration{
    {"link",
     "Local vs distributed haptic rendering through an injected-latency, lossy link (link_bench.json)",
     20, setup_link_bench}};

}  // namespace

}  // namespace tridex::bench
